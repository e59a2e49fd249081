// `rocking serve`: the browser lab. A local web server (cpp-httplib) that
// serves the lab's page (lab/: plain JavaScript, uPlot from npm) and its JSON
// API (rocking.lab: the same runs as the command line). It binds 127.0.0.1
// unless told otherwise, serves only the files of the lab's folder it read at
// start-up (no request names a file), bounds the request size and the runs in
// flight, and stops cleanly on Ctrl-C.
#include "commands.hpp"
#include "stop_signals.hpp"
#include <httplib.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>
#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <semaphore>
#include <sstream>
#include <thread>
import rocking.lab;

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

// JSON answers go uncompressed: httplib compresses only an exact
// "application/json", with Brotli at its slowest setting when the browser
// accepts it (most of a second for a run's history); on loopback that buys nothing.
constexpr const char* json_type = "application/json; charset=utf-8";

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

int run(const ServeOptions& o) {
  if (o.port < 0 || o.port > 65535) throw InputError(fmt::format("--port {}: must be in [0, 65535]", o.port));
  if (o.runs < 0) throw InputError(fmt::format("--runs {}: must be 0 (the cores) or more", o.runs));
  if (o.host != "127.0.0.1" && o.host != "localhost" && o.host != "::1")
    spdlog::warn("serving on {}: anyone who reaches this machine there can run simulations on it", o.host);
  const auto files = read_lab(o.lab);
  const Lab lab({.scenes = ROCKING_SCENES_DIR, .records = records_folder(o.records)});
  const int runs = o.runs > 0 ? o.runs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  auto slots = std::make_shared<std::counting_semaphore<1024>>(std::min(runs, 1024));

  httplib::Server server;
  // Workers wait on sockets more than they compute: runs are bounded by `slots`.
  server.new_task_queue = [] { return new httplib::ThreadPool(16); };
  server.set_payload_max_length(std::max(lab.limits().request_bytes, lab.limits().upload_bytes));
  server.set_keep_alive_timeout(2);
  server.set_tcp_nodelay(true);  // an answer leaves whole, not held back for the client's acknowledgement
  server.set_default_headers({{"X-Content-Type-Options", "nosniff"},
                              {"Content-Security-Policy", "default-src 'self'; img-src 'self' data:"},
                              {"Cache-Control", "no-store"}});
  const auto api = [&lab, slots](const httplib::Request& req, httplib::Response& res) {
    struct Slot {  // a run's place among those in flight, held while it computes
      std::counting_semaphore<1024>* s;
      explicit Slot(std::counting_semaphore<1024>* s) : s(s) {
        if (s) s->acquire();
      }
      ~Slot() {
        if (s) s->release();
      }
    } slot(req.method == "POST" ? slots.get() : nullptr);
    const LabAnswer a = lab.answer(req.method, req.path, req.body);
    res.status = a.status;
    res.set_content(a.body, json_type);
  };
  server.Get(R"(/api/.*)", api);
  server.Post(R"(/api/.*)", api);
  server.Get(R"(/.*)", [&files](const httplib::Request& req, httplib::Response& res) {
    const auto it = files.find(req.path);
    if (it == files.end()) {
      res.status = 404;
      res.set_content(R"({"error":"no such page"})", json_type);
      return;
    }
    res.set_content(it->second.content, it->second.type.c_str());
  });
  // httplib's own refusals (a body over the limit, a bad request line) get the one-line message too.
  server.set_error_handler([&lab](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;
    const std::string message =
        res.status == 413 ? fmt::format("a request over {} bytes", std::max(lab.limits().request_bytes,
                                                                             lab.limits().upload_bytes))
                          : fmt::format("the server refused the request (HTTP {})", res.status);
    res.set_content(fmt::format(R"({{"error":"{}"}})", message), json_type);
  });
  // What the lab does not answer itself (it answers every input error): memory, or a fault of ours.
  server.set_exception_handler([](const httplib::Request& req, httplib::Response& res, std::exception_ptr e) {
    std::string what = "unknown";
    try {
      std::rethrow_exception(e);
    } catch (const std::bad_alloc&) {
      what = "out of memory";
    } catch (const std::exception& x) {
      what = x.what();
    } catch (...) {
    }
    spdlog::error("{} {}: {}", req.method, req.path, what);
    res.status = 500;
    res.set_content(nlohmann::json{{"error", "the server failed on this request (" + what + "); please report it"}}
                        .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                    json_type);
  });

  const int port = o.port == 0 ? server.bind_to_any_port(o.host) : (server.bind_to_port(o.host, o.port) ? o.port : -1);
  if (port <= 0)
    throw InputError(fmt::format("--host {} --port {}: cannot listen there (in use? --port 0 picks a free one)", o.host,
                                 o.port));
  const std::string shown = o.host.find(':') != std::string::npos ? "[" + o.host + "]" : o.host;
  fmt::print("rocking serve: the lab is at http://{}:{}/ (Ctrl-C stops it)\n", shown, port);
  std::fflush(stdout);
  catch_stop_signals();
  std::jthread watcher([&server](std::stop_token stop) {
    while (!stop.stop_requested() && stop_signal() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    server.stop();
  });
  server.listen_after_bind();
  watcher.request_stop();
  const int signal = stop_signal();
  if (signal != 0) {
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
  cmd->footer(
      "Examples:\n"
      "  rocking serve                      then open http://127.0.0.1:8080/\n"
      "  rocking serve --port 0             a free port, printed\n"
      "  curl -s localhost:8080/api/simulate -d '{\"record\": \"elcentro_1940_ns.at2\", \"scale\": 2}'");
  return [o]() { return run(*o); };
}

}  // namespace rocking::app
