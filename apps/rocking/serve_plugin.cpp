// librocking_serve.so: the web server of `rocking serve` (cpp-httplib), opened
// by the program only for that command so that no other command loads
// cpp-httplib, OpenSSL, zlib and Brotli (plugins.hpp). It serves the page's
// files the program read and hands every /api/ request to the program
// (serve_plugin.hpp); it exposes one C symbol, rocking_serve.
//
// A classroom shares one server, so no client may hold more of it than its
// request needs. httplib reads a connection through its Stream; here that
// stream is our own (GuardedStream), which gives each request a deadline that
// grows only with the bytes that came (a client that sends half a body, or a
// byte a second, is cut off and its thread freed) and a ceiling on its bytes.
// POST bodies are read as they arrive and refused (413) at their endpoint's
// limit, chunked or not, before they are held whole. A request from a foreign
// page (an Origin that is not ours) or addressed to a foreign name (a Host
// that is not ours: DNS rebinding) is refused.
#include "serve_plugin.hpp"
#include <httplib.h>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <chrono>
#include <cstring>
#include <exception>
#include <map>
#include <new>
#include <string>
#include <thread>
#include <vector>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace {

using Clock = std::chrono::steady_clock;

// JSON answers go uncompressed: httplib compresses only an exact
// "application/json", with Brotli at its slowest setting when the browser
// accepts it (most of a second for a run's history); on loopback that buys nothing.
constexpr const char* json_type = "application/json; charset=utf-8";

// A request's line and headers may take this many bytes beyond its body.
constexpr std::size_t header_bytes = 64 * 1024;

void respond(void* response, int status, const char* body, std::size_t size) {
  auto* res = static_cast<httplib::Response*>(response);
  res->status = status;
  res->set_content(std::string(body, size), json_type);
}

std::string json_error(const std::string& message) {
  return nlohmann::json{{"error", message}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// The Content-Length a request announces (0 when none).
std::size_t content_length(const httplib::Request& req) {
  return req.has_header("Content-Length") ? std::strtoull(req.get_header_value("Content-Length").c_str(), nullptr, 10)
                                          : 0;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// "12 KB", "4 MB": a limit as a person reads it.
std::string bytes_text(std::size_t n) {
  if (n >= (1u << 20) && n % (1u << 20) == 0) return std::to_string(n >> 20) + " MB";
  if (n >= 1024 && n % 1024 == 0) return std::to_string(n >> 10) + " KB";
  return std::to_string(n) + " bytes";
}

// Whether `fd` becomes ready for `events` within `ms` milliseconds.
bool ready(int fd, short events, long long ms) {
  if (ms <= 0) return false;
  pollfd p{fd, events, 0};
  for (;;) {
    const int r = ::poll(&p, 1, static_cast<int>(std::min<long long>(ms, 1 << 30)));
    if (r < 0 && errno == EINTR) continue;
    return r > 0;
  }
}

// A connection's socket as httplib reads and writes it: buffered reads, each
// request with its deadline and its ceiling of bytes (begin_request).
class GuardedStream final : public httplib::Stream {
 public:
  GuardedStream(int fd, const RockingServeLimits& limits, std::size_t max_bytes)
      : fd_(fd), limits_(limits), max_bytes_(max_bytes) {}

  void begin_request() {
    start_ = Clock::now();
    received_ = 0;
  }
  bool has_buffered() const { return begin_ < end_; }
  bool timed_out() const { return timed_out_; }
  bool too_large() const { return too_large_; }

  bool is_readable() const override { return has_buffered() || ready(fd_, POLLIN, allowance_ms()); }
  bool is_writable() const override { return ready(fd_, POLLOUT, write_ms); }

  ssize_t read(char* ptr, std::size_t size) override {
    if (!has_buffered()) {
      if (received_ >= max_bytes_) {
        too_large_ = true;
        return -1;
      }
      if (!ready(fd_, POLLIN, allowance_ms())) {
        timed_out_ = true;
        return -1;
      }
      const ssize_t n = ::recv(fd_, buffer_, sizeof buffer_, 0);
      if (n <= 0) return n;
      begin_ = 0;
      end_ = static_cast<std::size_t>(n);
      received_ += end_;
    }
    const std::size_t n = std::min(size, end_ - begin_);
    std::memcpy(ptr, buffer_ + begin_, n);
    begin_ += n;
    return static_cast<ssize_t>(n);
  }

  ssize_t write(const char* ptr, std::size_t size) override {
    if (!ready(fd_, POLLOUT, write_ms)) return -1;
    return ::send(fd_, ptr, size, MSG_NOSIGNAL);
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override { address(::getpeername, ip, port); }
  void get_local_ip_and_port(std::string& ip, int& port) const override { address(::getsockname, ip, port); }
  socket_t socket() const override { return fd_; }

 private:
  static constexpr long long write_ms = 10000;  // a client that reads its answer slower than that is dropped

  // What is left of the request's allowance: request_seconds, plus a second
  // for every request_bytes_per_second bytes received.
  long long allowance_ms() const {
    const double allowed = limits_.request_seconds + static_cast<double>(received_) /
                                                         static_cast<double>(limits_.request_bytes_per_second);
    const auto spent = std::chrono::duration<double>(Clock::now() - start_).count();
    return static_cast<long long>((allowed - spent) * 1000);
  }

  template <class Name>
  void address(Name name, std::string& ip, int& port) const {
    sockaddr_storage a{};
    socklen_t len = sizeof a;
    ip.clear();
    port = 0;
    if (name(fd_, reinterpret_cast<sockaddr*>(&a), &len) != 0) return;
    char text[INET6_ADDRSTRLEN] = {};
    if (a.ss_family == AF_INET) {
      const auto* v4 = reinterpret_cast<const sockaddr_in*>(&a);
      ::inet_ntop(AF_INET, &v4->sin_addr, text, sizeof text);
      port = ntohs(v4->sin_port);
    } else if (a.ss_family == AF_INET6) {
      const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&a);
      ::inet_ntop(AF_INET6, &v6->sin6_addr, text, sizeof text);
      port = ntohs(v6->sin6_port);
    }
    ip = text;
  }

  int fd_;
  RockingServeLimits limits_;
  std::size_t max_bytes_;
  Clock::time_point start_ = Clock::now();
  std::size_t received_ = 0;
  bool timed_out_ = false, too_large_ = false;
  char buffer_[16 * 1024];
  std::size_t begin_ = 0, end_ = 0;
};

// Set by a handler that answered before reading the request's body: the
// connection is closed after the answer, not read on as if the rest of the
// body were the next request.
thread_local bool close_after_answer = false;

// httplib's server, each connection read through a GuardedStream.
class GuardedServer final : public httplib::Server {
 public:
  GuardedServer(const RockingServeLimits& limits, std::size_t max_bytes) : limits_(limits), max_bytes_(max_bytes) {}

 private:
  static constexpr int requests_per_connection = 100;

  bool process_and_close_socket(socket_t sock) override {
    GuardedStream stream(sock, limits_, max_bytes_);
    const auto keep_alive_ms = static_cast<long long>(limits_.keep_alive_seconds * 1000);
    for (int k = 0; k < requests_per_connection && is_running(); ++k) {
      stream.begin_request();  // the first request's wait for its first byte counts against its allowance
      if (k > 0 && !stream.has_buffered() && !ready(sock, POLLIN, keep_alive_ms)) break;
      close_after_answer = false;
      bool connection_closed = false;
      const bool ok =
          process_request(stream, k + 1 == requests_per_connection, connection_closed, [](httplib::Request&) {});
      if (!ok || connection_closed || close_after_answer || stream.timed_out() || stream.too_large()) break;
    }
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
    return true;
  }

  RockingServeLimits limits_;
  std::size_t max_bytes_;
};

// The Host header's name, without its port ("[::1]:8080" -> "[::1]").
std::string host_name(const std::string& host) {
  if (host.starts_with('[')) {
    const auto end = host.find(']');
    return end == std::string::npos ? host : host.substr(0, end + 1);
  }
  const auto colon = host.rfind(':');
  return colon == std::string::npos ? host : host.substr(0, colon);
}

// Why a request is refused for where it comes from or what it is addressed
// to; empty when it is not.
std::string foreign(const httplib::Request& req, const RockingServeConfig& c) {
  const bool has_host = req.has_header("Host");
  const std::string host = lower(req.get_header_value("Host"));
  if (has_host) {
    const std::string name = host_name(host);
    bool known = false;
    for (std::size_t i = 0; i < c.host_count && !known; ++i) known = name == lower(c.hosts[i]);
    if (!known)
      return "this server answers requests addressed to " + std::string(c.host_count > 0 ? c.hosts[0] : "it") +
             " (or another of its own names), not to '" + name.substr(0, 60) + "'";
  }
  if (req.has_header("Origin")) {
    const std::string origin = lower(req.get_header_value("Origin"));
    if (!has_host || origin != "http://" + host)
      return "requests from other web pages are refused: open the lab at its own address";
  }
  return {};
}

void refuse(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(json_error(message), json_type);
  close_after_answer = true;
}

std::string too_large(const std::string& path, std::size_t limit) {
  return "the request is too large for " + path + " (at most " + bytes_text(limit) + ", " + std::to_string(limit) +
         " bytes)" + (path == "/api/upload" ? ": upload a shorter record" : "");
}

// Before any body is read: where the request comes from, what it is
// addressed to, and the size it announces.
void screen_requests(GuardedServer& server, const RockingServeConfig& c) {
  server.set_pre_routing_handler([&c](const httplib::Request& req, httplib::Response& res) {
    if (const std::string why = foreign(req, c); !why.empty()) {
      refuse(res, 403, why);
      return httplib::Server::HandlerResponse::Handled;
    }
    const bool body = req.has_header("Transfer-Encoding") || content_length(req) > 0;
    if (req.method != "POST" && body) {
      refuse(res, 400, req.method + " " + req.path + " takes no body");
      return httplib::Server::HandlerResponse::Handled;
    }
    if (req.method == "POST") {
      const std::size_t limit = std::min(c.payload_max, c.body_limit(c.context, req.path.c_str()));
      if (content_length(req) > limit) {
        refuse(res, 413, too_large(req.path, limit));
        return httplib::Server::HandlerResponse::Handled;
      }
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
}

// The API's GETs and POSTs to the program's answer, every other GET to the
// page's files.
void route_requests(GuardedServer& server, const RockingServeConfig& c,
                    const std::map<std::string, const RockingServeFile*>& files) {
  server.Get(R"(/api/.*)", [&c](const httplib::Request& req, httplib::Response& res) {
    c.answer(c.context, req.method.c_str(), req.path.c_str(), "", 0, &res, respond);
  });
  // A POST's body read as it arrives, up to its endpoint's limit.
  server.Post(R"(/api/.*)", [&c](const httplib::Request& req, httplib::Response& res,
                                 const httplib::ContentReader& reader) {
    const std::size_t limit = std::min(c.payload_max, c.body_limit(c.context, req.path.c_str()));
    std::string body;
    bool over = false;
    const bool read = reader([&](const char* data, std::size_t size) {
      if (body.size() + size > limit) {
        over = true;
        return false;
      }
      body.append(data, size);
      return true;
    });
    if (over) return refuse(res, 413, too_large(req.path, limit));
    if (!read) return refuse(res, 400, "the request's body did not arrive whole (too slow, or cut off)");
    c.answer(c.context, req.method.c_str(), req.path.c_str(), body.data(), body.size(), &res, respond);
  });
  server.Get(R"(/.*)", [&files](const httplib::Request& req, httplib::Response& res) {
    const auto it = files.find(req.path);
    if (it == files.end()) {
      res.status = 404;
      res.set_content(R"({"error":"no such page"})", json_type);
      return;
    }
    res.set_content(std::string(it->second->content, it->second->size), it->second->type);
  });
}

// httplib's own refusals and what the program does not answer itself.
void answer_failures(GuardedServer& server, const RockingServeConfig& c) {
  // httplib's refusals (a bad request line, a request cut off) get the one-line message too.
  server.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;
    close_after_answer = true;
    res.set_content(json_error("the server refused the request (HTTP " + std::to_string(res.status) + ")"),
                    json_type);
  });
  // Memory, or a fault of ours.
  server.set_exception_handler([&c](const httplib::Request& req, httplib::Response& res, std::exception_ptr e) {
    std::string what = "unknown";
    try {
      std::rethrow_exception(e);
    } catch (const std::bad_alloc&) {
      what = "out of memory";
    } catch (const std::exception& x) {
      what = x.what();
    } catch (...) {
    }
    c.log_error(c.context, (req.method + " " + req.path + ": " + what).c_str());
    res.status = 500;
    res.set_content(json_error("the server failed on this request (" + what + "); please report it"), json_type);
  });
}

// Binds the configured address and answers until the program asks to stop.
int listen_until_stopped(GuardedServer& server, const RockingServeConfig& c) {
  // The listening socket: SO_REUSEADDR only, so that a restarted server gets
  // its port back at once while a second server on a port in use is refused
  // (httplib's default, SO_REUSEPORT, lets both listen and share the requests).
  int listening_socket = -1;
  server.set_socket_options([&listening_socket](socket_t sock) {
    const int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    listening_socket = sock;
  });
  const int port = c.port == 0 ? server.bind_to_any_port(c.host) : (server.bind_to_port(c.host, c.port) ? c.port : -1);
  if (port <= 0) return rocking_serve_cannot_bind;
  // httplib listens with a backlog of 5: more clients connecting at once than
  // that overflow the queue, the kernel drops their handshakes, and a request
  // resent after the server's keep-alive wait finds its connection closed.
  // Listening again on the same socket only enlarges the queue.
  if (listening_socket >= 0) ::listen(listening_socket, SOMAXCONN);
  c.listening(c.context, port);
  // httplib's stop() acts only on a server whose listening loop has begun: a
  // Ctrl-C that comes between the address printed and that loop waits for it.
  std::jthread watcher([&server, &c](std::stop_token stop) {
    while (!stop.stop_requested()) {
      if (c.stop_requested(c.context) != 0 && server.is_running()) {
        server.stop();
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  server.listen_after_bind();
  watcher.request_stop();
  return c.stop_requested(c.context) != 0 ? rocking_serve_stopped : rocking_serve_ended;
}

int serve(const RockingServeConfig& c) {
  std::map<std::string, const RockingServeFile*> files;
  for (std::size_t i = 0; i < c.file_count; ++i) files[c.files[i].url] = &c.files[i];

  GuardedServer server(c.limits, c.payload_max + header_bytes + c.payload_max / 8);
  // Workers mostly wait on sockets; the program bounds the runs computed at once.
  server.new_task_queue = [&c] { return new httplib::ThreadPool(static_cast<std::size_t>(std::max(4, c.limits.connections))); };
  server.set_payload_max_length(c.payload_max);
  server.set_tcp_nodelay(true);  // an answer leaves whole, not held back for the client's acknowledgement
  server.set_default_headers({{"X-Content-Type-Options", "nosniff"},
                              {"Content-Security-Policy", "default-src 'self'; img-src 'self' data:"},
                              {"Cache-Control", "no-store"}});
  screen_requests(server, c);
  route_requests(server, c, files);
  answer_failures(server, c);
  return listen_until_stopped(server, c);
}

}  // namespace

extern "C" __attribute__((visibility("default"))) int rocking_serve(const RockingServeConfig* config) {
  try {
    return serve(*config);
  } catch (const std::exception& e) {
    config->log_error(config->context, e.what());
  } catch (...) {
    config->log_error(config->context, "unknown failure");
  }
  return rocking_serve_ended;
}
