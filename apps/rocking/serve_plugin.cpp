// librocking_serve.so: the web server of `rocking serve` (cpp-httplib), opened
// by the program only for that command so that no other command loads
// cpp-httplib, OpenSSL, zlib and Brotli (plugins.hpp). It serves the page's
// files the program read and hands every /api/ request to the program
// (serve_plugin.hpp); it exposes one C symbol, rocking_serve.
#include "serve_plugin.hpp"
#include <httplib.h>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <chrono>
#include <exception>
#include <map>
#include <new>
#include <string>
#include <thread>
#include <sys/socket.h>

namespace {

// JSON answers go uncompressed: httplib compresses only an exact
// "application/json", with Brotli at its slowest setting when the browser
// accepts it (most of a second for a run's history); on loopback that buys nothing.
constexpr const char* json_type = "application/json; charset=utf-8";

void respond(void* response, int status, const char* body, std::size_t size) {
  auto* res = static_cast<httplib::Response*>(response);
  res->status = status;
  res->set_content(std::string(body, size), json_type);
}

std::string json_error(const std::string& message) {
  return nlohmann::json{{"error", message}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

int serve(const RockingServeConfig& c) {
  std::map<std::string, const RockingServeFile*> files;
  for (std::size_t i = 0; i < c.file_count; ++i) files[c.files[i].url] = &c.files[i];

  httplib::Server server;
  // Workers wait on sockets more than they compute: the program bounds the runs.
  server.new_task_queue = [] { return new httplib::ThreadPool(16); };
  server.set_payload_max_length(c.payload_max);
  server.set_keep_alive_timeout(2);
  server.set_tcp_nodelay(true);  // an answer leaves whole, not held back for the client's acknowledgement
  server.set_default_headers({{"X-Content-Type-Options", "nosniff"},
                              {"Content-Security-Policy", "default-src 'self'; img-src 'self' data:"},
                              {"Cache-Control", "no-store"}});
  const auto api = [&c](const httplib::Request& req, httplib::Response& res) {
    c.answer(c.context, req.method.c_str(), req.path.c_str(), req.body.data(), req.body.size(), &res, respond);
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
    res.set_content(std::string(it->second->content, it->second->size), it->second->type);
  });
  // httplib's own refusals (a body over the limit, a bad request line) get the one-line message too.
  server.set_error_handler([&c](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;
    const std::string message = res.status == 413 ? "a request over " + std::to_string(c.payload_max) + " bytes"
                                                  : "the server refused the request (HTTP " +
                                                        std::to_string(res.status) + ")";
    res.set_content(json_error(message), json_type);
  });
  // What the program does not answer itself: memory, or a fault of ours.
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
