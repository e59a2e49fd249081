// `rocking serve` under a classroom's load and a hostile page: a chunked
// body of 300 MB is refused as it arrives and the server's memory stays under
// 200 MB; 40 clients that hold half-sent bodies (or send a byte a second) do
// not keep others from an answer within 3 s, and are cut off; requests from a
// foreign Origin or addressed to a foreign Host are refused; a form-encoded
// body (curl -d) is taken up to the lab's limit and refused beyond it with
// that limit in words; errors name no absolute path; --help states the
// limits; 30 clients moving sliders at once each get every answer, the same
// answer as alone (how fast is measured by `make bench`: lab_bench's classroom).
#include <doctest/doctest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>
#include "records.hpp"
#include "run_program.hpp"
#include "serve_process.hpp"

using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// A raw TCP connection to the server, for requests no well-behaved client sends.
struct Socket {
  int fd = -1;
  explicit Socket(int port) {
    fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
      ::close(fd);
      fd = -1;
    }
  }
  ~Socket() {
    if (fd >= 0) ::close(fd);
  }
  // Sends all of `s`; false once the server has closed or reset the connection.
  bool send(const std::string& s) const {
    for (std::size_t at = 0; at < s.size();) {
      const ssize_t n = ::send(fd, s.data() + at, s.size() - at, MSG_NOSIGNAL);
      if (n <= 0) return false;
      at += static_cast<std::size_t>(n);
    }
    return true;
  }
  // What the server sent within `limit` (until it closed, or the limit passed).
  std::string receive(std::chrono::milliseconds limit) const {
    std::string got;
    const auto end = Clock::now() + limit;
    char buf[4096];
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now()).count();
      pollfd p{fd, POLLIN, 0};
      if (left <= 0 || ::poll(&p, 1, static_cast<int>(left)) <= 0) break;
      const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
      if (n <= 0) break;
      got.append(buf, static_cast<std::size_t>(n));
    }
    return got;
  }
  // Whether the server has closed the connection within `limit` (whatever it sent before, read and dropped).
  bool closed_by_server(std::chrono::milliseconds limit) const {
    const auto end = Clock::now() + limit;
    char buf[4096];
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now()).count();
      pollfd p{fd, POLLIN, 0};
      if (left <= 0 || ::poll(&p, 1, static_cast<int>(left)) <= 0) return false;
      if (::recv(fd, buf, sizeof buf, 0) <= 0) return true;
    }
  }
};

std::string status_line(const std::string& response) { return response.substr(0, response.find("\r\n")); }

std::string body_of(const std::string& response) {
  const auto at = response.find("\r\n\r\n");
  return at == std::string::npos ? "" : response.substr(at + 4);
}

}  // namespace

TEST_CASE("a chunked POST of 300 MB is refused as it arrives, and the server's memory stays under 200 MB") {
  Server server("");
  REQUIRE(server.port > 0);
  Socket s(server.port);
  REQUIRE(s.fd >= 0);
  REQUIRE(s.send("POST /api/simulate HTTP/1.1\r\nHost: 127.0.0.1\r\nTransfer-Encoding: chunked\r\n"
                 "Content-Type: application/json\r\n\r\n"));
  const std::string chunk = "10000\r\n" + std::string(0x10000, ' ') + "\r\n";  // 64 KB of blanks
  std::size_t sent = 0;
  while (sent < 300u << 20 && s.send(chunk)) sent += 0x10000;
  const std::string response = s.receive(std::chrono::seconds(5));
  MESSAGE("sent " << sent / 1024 << " KB of the body before the server refused it; server peak "
                  << server.peak_mb() << " MB");
  CHECK(status_line(response) == "HTTP/1.1 413 Payload Too Large");
  const std::string message = json::parse(body_of(response))["error"];
  CHECK_MESSAGE(message.find("at most 64 KB") != std::string::npos, message);
  CHECK(sent < 300u << 20);  // refused before the end
  CHECK(server.peak_mb() < 200);
  // A Content-Length over the limit is refused before its body is sent.
  Socket t(server.port);
  REQUIRE(t.send("POST /api/upload HTTP/1.1\r\nHost: localhost\r\nContent-Length: 314572800\r\n\r\n"));
  const std::string early = t.receive(std::chrono::seconds(3));
  CHECK(status_line(early) == "HTTP/1.1 413 Payload Too Large");
  CHECK(body_of(early).find("at most 4 MB") != std::string::npos);
  // Still serving.
  httplib::Client client("127.0.0.1", server.port);
  CHECK(client.Get("/api/scenes")->status == 200);
}

TEST_CASE("40 clients holding half-sent bodies, or sending a byte a second, leave others an answer within 3 s") {
  Server server("");
  REQUIRE(server.port > 0);
  std::vector<std::unique_ptr<Socket>> slow;
  for (int i = 0; i < 40; ++i) {
    slow.push_back(std::make_unique<Socket>(server.port));
    REQUIRE(slow.back()->fd >= 0);
    REQUIRE(slow.back()->send("POST /api/simulate HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 1000\r\n\r\n" +
                              std::string(500, ' ')));
  }
  // Forty more that trickle their headers, a byte a second.
  std::atomic<bool> stop{false};
  std::vector<std::unique_ptr<Socket>> trickle;
  for (int i = 0; i < 40; ++i) trickle.push_back(std::make_unique<Socket>(server.port));
  std::thread trickler([&] {
    const std::string request = "GET /api/scenes HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: " + std::string(100, 'x');
    for (std::size_t k = 0; k < request.size() && !stop; ++k) {
      for (const auto& t : trickle) t->send(request.substr(k, 1));
      std::this_thread::sleep_for(std::chrono::seconds(1));
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  std::vector<double> waits;
  for (int k = 0; k < 3; ++k) {
    httplib::Client client("127.0.0.1", server.port);
    client.set_read_timeout(20);
    const auto t0 = Clock::now();
    const auto r = client.Get("/api/scenes");
    waits.push_back(seconds_since(t0));
    CHECK(r);
    if (r) CHECK(r->status == 200);
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
  }
  MESSAGE("GET /api/scenes while 40 clients hold half a body and 40 trickle: " << waits[0] << ", " << waits[1]
                                                                                 << ", " << waits[2] << " s");
  for (double w : waits) CHECK(w < 3);
  // The slow clients are cut off once their allowance (5 s, plus a second per 16 KB) is spent.
  std::this_thread::sleep_for(std::chrono::seconds(5));
  int cut = 0;
  for (const auto& s : slow) cut += s->closed_by_server(std::chrono::milliseconds(100));
  int cut_trickle = 0;
  for (const auto& t : trickle) cut_trickle += t->closed_by_server(std::chrono::milliseconds(100));
  stop = true;
  trickler.join();
  CHECK(cut == 40);
  CHECK(cut_trickle == 40);
}

TEST_CASE("requests from a foreign Origin or addressed to a foreign Host are refused, and the lab's own are answered") {
  Server server("");
  REQUIRE(server.port > 0);
  const std::string own = "127.0.0.1:" + std::to_string(server.port);
  const std::string body = R"({"scene": "rigid_block"})";
  const auto post = [&](const httplib::Headers& headers) {
    httplib::Client client("127.0.0.1", server.port);
    client.set_read_timeout(60);
    return client.Post("/api/simulate", headers, body, "application/json");
  };
  const auto evil = post({{"Origin", "http://evil.example"}});
  REQUIRE(evil);
  CHECK(evil->status == 403);
  CHECK(json::parse(evil->body)["error"].get<std::string>().find("other web pages") != std::string::npos);
  const auto evil_port = post({{"Origin", "http://127.0.0.1:1"}});
  REQUIRE(evil_port);
  CHECK(evil_port->status == 403);
  // DNS rebinding: a page of evil.example whose name now resolves to this machine.
  const auto rebound = post({{"Host", "evil.example:" + std::to_string(server.port)},
                             {"Origin", "http://evil.example:" + std::to_string(server.port)}});
  REQUIRE(rebound);
  CHECK(rebound->status == 403);
  CHECK(json::parse(rebound->body)["error"].get<std::string>().find("'evil.example'") != std::string::npos);
  httplib::Client client("127.0.0.1", server.port);
  client.set_default_headers({{"Host", "evil.example"}});
  const auto page = client.Get("/");
  REQUIRE(page);
  CHECK(page->status == 403);
  // The page's own requests: its Origin is the address it was opened at.
  const auto mine = post({{"Origin", "http://" + own}});
  REQUIRE(mine);
  CHECK(mine->status == 200);
  const auto by_name = post({{"Host", "localhost:" + std::to_string(server.port)},
                             {"Origin", "http://localhost:" + std::to_string(server.port)}});
  REQUIRE(by_name);
  CHECK(by_name->status == 200);
}

TEST_CASE("a curl -d body is taken up to the lab's limit and refused beyond it with that limit, and errors name no path") {
  const auto records = records_dir();
  if (!records) return;
  Server server("--records " + *records);
  REQUIRE(server.port > 0);
  httplib::Client client("127.0.0.1", server.port);
  client.set_read_timeout(60);
  // curl -d sends application/x-www-form-urlencoded; 20 KB of JSON (blanks after it) is a run.
  const std::string padded = R"({"scene": "rigid_block"})" + std::string(20 * 1024, ' ');
  const auto ok = client.Post("/api/simulate", padded, "application/x-www-form-urlencoded");
  REQUIRE(ok);
  CHECK(ok->status == 200);
  const auto over = client.Post("/api/simulate", std::string(70 * 1024, ' '), "application/x-www-form-urlencoded");
  REQUIRE(over);
  CHECK(over->status == 413);
  const std::string message = json::parse(over->body)["error"];
  CHECK_MESSAGE(message == "the request is too large for /api/simulate (at most 64 KB, 65536 bytes)", message);
  // A bad override and a bad record answer without the machine's folders.
  for (const std::string& bad : {std::string(R"({"set": ["structure.EI_scale=-1"]})"),
                                 std::string(R"({"set": ["nonsense.key=1"]})"),
                                 std::string(R"({"record": "elcentro_1940_ns.at2", "component": "UD"})")}) {
    const auto r = client.Post("/api/simulate", bad, "application/json");
    REQUIRE(r);
    CAPTURE(r->body);
    CHECK(r->status == 400);
    CHECK(r->body.find(ROCKING_SOURCE_DIR) == std::string::npos);
    CHECK(r->body.find(*records) == std::string::npos);
    CHECK(r->body.find("\"/") == std::string::npos);
    CHECK(r->body.find(" /") == std::string::npos);
  }
  // A vertical component, uploaded: told in words what to upload instead, not a command-line flag.
  std::ifstream file(*records + "/formats/us1000hyfh_akbmrp_bnz.V2c");
  std::ostringstream text;
  text << file.rdbuf();
  const auto up = client.Post("/api/upload", json{{"name", "akbmrp_bnz.V2c"}, {"text", text.str()}}.dump(),
                              "application/json");
  REQUIRE(up);
  CHECK(up->status == 400);
  const std::string said = json::parse(up->body)["error"];
  CHECK_MESSAGE(said.find("akbmrp_bnz.V2c is the vertical component (BNZ)") != std::string::npos, said);
  CHECK(said.find("upload a horizontal component") != std::string::npos);
  CHECK(said.find("--") == std::string::npos);
  CHECK(said.find("/tmp") == std::string::npos);
}

TEST_CASE("rocking serve --help states the limits a client meets") {
  const Result help = run("serve --help");
  CHECK(help.code == 0);
  for (const char* says : {"at most 64 KB", "4 MB", "within 5 s, plus 1 s per 16 KB", "connections served at once 96",
                           "another Origin: 403", "another Host: 403", "200 s simulated"})
    CHECK_MESSAGE(help.out.find(says) != std::string::npos, says);
}

TEST_CASE("30 students moving sliders on one server at once each get every answer, the one they get alone") {
  const auto records = records_dir();
  if (!records) return;
  Server server("--records " + *records);
  REQUIRE(server.port > 0);
  constexpr int students = 30;
  constexpr int moves = 6;
  constexpr int positions = 20;  // slider positions: damper thickness 1, 1.05, ..., 1.95
  const auto request = [](int position) {
    return json{{"scene", "christchurch_chimney"},
                {"record", "elcentro_1940_ns.at2"},
                {"scale", 3},
                {"set", {"damper.thickness=" + std::to_string(1 + 0.05 * position)}}}
        .dump();
  };
  // An answer without the one field that differs between runs of the same request: the wall time.
  const auto answer = [](const std::string& body) {
    json a = json::parse(body);
    a["summary"].erase("wall_s");
    return a;
  };
  // Each position's answer when it is the only request in the server.
  std::vector<json> alone(positions);
  {
    httplib::Client c("127.0.0.1", server.port);
    c.set_read_timeout(600);
    for (int p = 0; p < positions; ++p) {
      const auto r = c.Post("/api/simulate", request(p), "application/json");
      REQUIRE(r);
      REQUIRE(r->status == 200);
      alone[static_cast<std::size_t>(p)] = answer(r->body);
    }
  }
  std::vector<int> bad(students, 0);
  std::vector<int> wrong(students, 0);
  std::vector<std::thread> threads;
  for (int i = 0; i < students; ++i)
    threads.emplace_back([&, i] {
      // Each student on the chimney under El Centro, as lesson 1 opens it, moving
      // the damper-thickness slider one step at a time. No pause between moves:
      // all 30 are in the server together. The timeout only ends a hung server.
      httplib::Client c("127.0.0.1", server.port);
      c.set_read_timeout(600);
      for (int k = 0; k < moves; ++k) {
        const int p = (i + k) % positions;
        const auto r = c.Post("/api/simulate", request(p), "application/json");
        if (!r || r->status != 200)
          ++bad[static_cast<std::size_t>(i)];
        else if (answer(r->body) != alone[static_cast<std::size_t>(p)])
          ++wrong[static_cast<std::size_t>(i)];
      }
    });
  for (std::thread& t : threads) t.join();
  for (int i = 0; i < students; ++i) {
    CHECK_MESSAGE(bad[static_cast<std::size_t>(i)] == 0, "student " << i << ": requests unanswered or refused");
    CHECK_MESSAGE(wrong[static_cast<std::size_t>(i)] == 0, "student " << i << ": answers not the ones given alone");
  }
}
