// `rocking serve`: the browser lab. A local web server that serves the lab's
// page (lab/: plain JavaScript, uPlot from npm) and its JSON API (rocking.lab:
// the same runs as the command line). It binds 127.0.0.1 unless told
// otherwise, serves only the files of the lab's folder it read at start-up (no
// request names a file), bounds the request size and the runs in flight, and
// stops cleanly on Ctrl-C. HTTP itself is cpp-httplib's, in librocking_serve.so
// (serve_plugin.hpp), which only this command opens.
#include "commands.hpp"
#include "plugins.hpp"
#include "serve_plugin.hpp"
#include "stop_signals.hpp"
#include <nlohmann/json.hpp>
#include "log.hpp"
#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <semaphore>
#include <sstream>
#include <string_view>
#include <thread>
#include <vector>
#include <ifaddrs.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <unistd.h>
import rocking.lab;
import rocking.errors;

namespace rocking::app {

namespace {

namespace fs = std::filesystem;

struct ServeOptions {
  std::string host = "127.0.0.1";
  int port = 8080;
  std::string lab = ROCKING_LAB_DIR;
  std::string records;
  int runs = 0;  // runs in flight at once; 0: the cores
};

struct StaticFile {
  std::string content, type;
};

std::string content_type(const fs::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".png") return "image/png";
  if (ext == ".svg") return "image/svg+xml";
  return "application/octet-stream";
}

// The page's files, read once: the lab folder's own (not its tests) and
// uPlot's from its node_modules, by the URL each is served at.
std::map<std::string, StaticFile> read_lab(const fs::path& dir) {
  std::map<std::string, StaticFile> files;
  const auto add = [&](const std::string& url, const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in) throw InputError(fmt::format("--lab {}: cannot read {}", dir.string(), file.string()));
    files[url] = {text.str(), content_type(file)};
  };
  std::error_code ec;
  if (!fs::is_regular_file(dir / "index.html", ec))
    throw InputError(fmt::format("--lab {}: no index.html there (the lab's folder is lab/ in the repository)",
                                 dir.string()));
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string ext = entry.path().extension().string();
    if (entry.is_regular_file() && (ext == ".html" || ext == ".js" || ext == ".css" || ext == ".svg"))
      add("/" + entry.path().filename().string(), entry.path());
  }
  files["/"] = files["/index.html"];
  const fs::path uplot = dir / "node_modules" / "uplot" / "dist";
  if (!fs::is_regular_file(uplot / "uPlot.iife.min.js", ec))
    throw InputError(fmt::format("--lab {}: uPlot is not installed in its node_modules (`make setup` installs it)",
                                 dir.string()));
  add("/vendor/uPlot.iife.min.js", uplot / "uPlot.iife.min.js");
  add("/vendor/uPlot.min.css", uplot / "uPlot.min.css");
  return files;
}

std::string records_folder(const std::string& given) {
  if (!given.empty()) return given;
  const char* env = std::getenv("ROCKING_RECORDS");
  return env != nullptr && *env != 0 ? env : ROCKING_RECORDS_DIR;
}

// What one client may hold of the server (serve_plugin.hpp), stated in --help.
constexpr RockingServeLimits client_limits{
    .request_seconds = 5, .request_bytes_per_second = 16 * 1024, .keep_alive_seconds = 2, .connections = 96};

bool loopback(const std::string& host) { return host == "127.0.0.1" || host == "localhost" || host == "::1"; }

// The names a browser may address this server by (its Host header, without
// the port): this machine's loopback names, and when it listens on the
// network, the address it was given or, for every address (0.0.0.0, ::),
// the machine's name and each of its interfaces' addresses.
std::vector<std::string> host_names(const std::string& host) {
  std::vector<std::string> names{"127.0.0.1", "localhost", "[::1]"};
  const auto bracket = [](const std::string& h) { return h.find(':') != std::string::npos ? "[" + h + "]" : h; };
  if (host != "0.0.0.0" && host != "::") {
    if (!loopback(host)) names.push_back(bracket(host));
    return names;
  }
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) == 0 && name[0] != 0) {
    names.emplace_back(name);
    names.push_back(std::string(name) + ".local");
  }
  ifaddrs* list = nullptr;
  if (::getifaddrs(&list) == 0) {
    for (const ifaddrs* a = list; a != nullptr; a = a->ifa_next) {
      if (a->ifa_addr == nullptr) continue;
      char text[INET6_ADDRSTRLEN] = {};
      if (a->ifa_addr->sa_family == AF_INET)
        ::inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(a->ifa_addr)->sin_addr, text, sizeof text);
      else if (a->ifa_addr->sa_family == AF_INET6)
        ::inet_ntop(AF_INET6, &reinterpret_cast<const sockaddr_in6*>(a->ifa_addr)->sin6_addr, text, sizeof text);
      if (text[0] != 0) names.push_back(bracket(text));
    }
    ::freeifaddrs(list);
  }
  return names;
}

// What the server plugin calls back (serve_plugin.hpp): the lab answers, a
// bounded number of runs at once.
struct Serving {
  const Lab& lab;
  std::string host;
  std::counting_semaphore<1024> slots;
};

void answer(void* context, const char* method, const char* path, const char* body, std::size_t body_size,
            void* response, RockingRespond respond) {
  auto& s = *static_cast<Serving*>(context);
  const bool post = std::string_view(method) == "POST";
  if (post) s.slots.acquire();  // a run's place among those in flight, held while it computes
  LabAnswer a;
  try {
    a = s.lab.answer(method, path, std::string_view(body, body_size));
  } catch (const std::exception& e) {  // the lab answers every input error itself: memory, or a fault of ours
    log::error("{} {}: {}", method, path, e.what());
    a = {500, nlohmann::json{{"error", "the server failed on this request (its log in the terminal says why); "
                                       "please report it"}}
                  .dump()};
  }
  if (post) s.slots.release();
  respond(response, a.status, a.body.data(), a.body.size());
}

int run(const ServeOptions& o) {
  if (o.port < 0 || o.port > 65535) throw InputError(fmt::format("--port {}: must be in [0, 65535]", o.port));
  if (o.runs < 0) throw InputError(fmt::format("--runs {}: must be 0 (the cores) or more", o.runs));
  if (!loopback(o.host))
    log::warn("serving on {}: anyone who reaches this machine there can run simulations on it", o.host);
  const auto files = read_lab(o.lab);
  const auto serve = reinterpret_cast<RockingServe>(
      plugin_symbol("librocking_serve.so", "rocking_serve", "the lab's web server"));
  const Lab lab({.scenes = ROCKING_SCENES_DIR, .records = records_folder(o.records)});
  const int runs = o.runs > 0 ? o.runs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  Serving serving{lab, o.host, std::counting_semaphore<1024>(std::min(runs, 1024))};

  const std::vector<std::string> names = host_names(o.host);
  std::vector<const char*> hosts;
  for (const std::string& n : names) hosts.push_back(n.c_str());
  std::vector<RockingServeFile> served;
  for (const auto& [url, file] : files)
    served.push_back({url.c_str(), file.content.data(), file.content.size(), file.type.c_str()});
  const RockingServeConfig config{
      .host = o.host.c_str(),
      .port = o.port,
      .payload_max = std::max(lab.limits().request_bytes, lab.limits().upload_bytes),
      .body_limit =
          [](void* context, const char* path) {
            const LabLimits& limits = static_cast<Serving*>(context)->lab.limits();
            return std::string_view(path) == "/api/upload" ? limits.upload_bytes : limits.request_bytes;
          },
      .limits = client_limits,
      .hosts = hosts.data(),
      .host_count = hosts.size(),
      .files = served.data(),
      .file_count = served.size(),
      .context = &serving,
      .answer = answer,
      .listening =
          [](void* context, int port) {
            const std::string& host = static_cast<Serving*>(context)->host;
            const std::string shown = host.find(':') != std::string::npos ? "[" + host + "]" : host;
            fmt::print("rocking serve: the lab is at http://{}:{}/ (Ctrl-C stops it)\n", shown, port);
            std::fflush(stdout);
          },
      .stop_requested = [](void*) { return stop_signal(); },
      .log_error = [](void*, const char* message) { log::error("{}", message); },
  };
  catch_stop_signals();
  const int result = serve(&config);
  if (result == rocking_serve_cannot_bind)
    throw InputError(fmt::format("--host {} --port {}: cannot listen there (in use? --port 0 picks a free one)", o.host,
                                 o.port));
  const int signal = stop_signal();
  if (result == rocking_serve_stopped && signal != 0) {
    fmt::print("rocking serve: stopped by {}\n", stop_signal_name(signal));
    return 0;
  }
  throw RunError("the server stopped listening");
}

}  // namespace

Command add_serve_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "serve",
      "The browser lab: a local web server with the lab's page, where sliders\n"
      "(damper thickness, scale, a tendon's prestress, restitution) re-run the\n"
      "structure and redraw it rocking, its traces and its devices' loops, beside\n"
      "a twin (fixed base, no dampers, no tendon); guided pages for the lessons of\n"
      "docs/teaching.md. Its JSON API runs what `rocking simulate`, `modal` and\n"
      "`ida` run: GET /api/scenes, /api/records; POST /api/simulate, /api/modal,\n"
      "/api/ida, and /api/upload (a record file of your own, read as --record\n"
      "reads it). Binds 127.0.0.1 (this machine only) unless --host says otherwise.\n"
      "Ctrl-C stops it.");
  auto o = std::make_shared<ServeOptions>();
  cmd->add_option("--port", o->port, "Port to listen on (default 8080; 0: a free one, printed)")->type_name("N");
  cmd->add_option("--host", o->host,
                  "Address to listen on (default 127.0.0.1: this machine only; 0.0.0.0\n"
                  "opens the lab to the network, with a warning)")
      ->type_name("ADDR");
  cmd->add_option("--records", o->records,
                  "Folder of the records the lab offers (default $ROCKING_RECORDS, else\n"
                  "../shared/data/records)")
      ->type_name("DIR");
  cmd->add_option("--lab", o->lab, "Folder of the lab's page (default: lab/ of the repository)")->type_name("DIR");
  cmd->add_option("--runs", o->runs, "Runs computed at once; more requests wait (default: the cores)")->type_name("N");
  const LabLimits lab_limits;
  cmd->footer(fmt::format(
      "Limits (what one client may ask of the server):\n"
      "  a run's request body       at most {} KB; an uploaded record's {} MB (413 beyond,\n"
      "                             refused as it arrives, chunked or not)\n"
      "  a request's arrival        within {:g} s, plus 1 s per {} KB of it; a slower client\n"
      "                             is cut off; an idle connection is closed after {:g} s\n"
      "  connections served at once {} (more wait); runs computed at once: --runs\n"
      "  a run                      at most {:g} s simulated, {} nodes, {} history rows,\n"
      "                             {:g} s of computing; an IDA at most {} levels\n"
      "  where requests come from   only pages of this server (another Origin: 403) and\n"
      "                             addressed to its own names (another Host: 403)\n\n"
      "Examples:\n"
      "  rocking serve                      then open http://127.0.0.1:8080/\n"
      "  rocking serve --port 0             a free port, printed\n"
      "  curl -s localhost:8080/api/simulate -d '{{\"record\": \"elcentro_1940_ns.at2\", \"scale\": 2}}'",
      lab_limits.request_bytes / 1024, lab_limits.upload_bytes >> 20, client_limits.request_seconds,
      client_limits.request_bytes_per_second / 1024, client_limits.keep_alive_seconds, client_limits.connections,
      lab_limits.duration, lab_limits.nodes, lab_limits.history_rows, lab_limits.seconds, lab_limits.ida_levels));
  return [o]() { return run(*o); };
}

}  // namespace rocking::app
