// What `rocking serve` hands librocking_serve.so (serve_plugin.cpp), the web
// server it opens only for that command (plugins.hpp): plain C types, so no
// object of either side's C++ library crosses. The program owns every
// answer (the lab's JSON API, rocking.lab) and the page's files; the plugin
// owns HTTP: sockets, threads, limits and headers.
#pragma once
#include <cstddef>

extern "C" {

// One file of the lab's page, served at `url` with its content type.
struct RockingServeFile {
  const char* url;
  const char* content;
  std::size_t size;
  const char* type;
};

// How the program answers a request: it calls respond(response, ...) once,
// and the plugin copies the body before respond returns.
using RockingRespond = void (*)(void* response, int status, const char* body, std::size_t size);

// What one client may hold of the server. A request (its line, headers and
// body) must arrive within `request_seconds`, plus one second for every
// `request_bytes_per_second` bytes of it: a client that sends slowly is cut
// off, and its thread serves others. `connections` are served at once; more
// wait for a free one.
struct RockingServeLimits {
  double request_seconds;              // 5
  std::size_t request_bytes_per_second;  // 16384
  double keep_alive_seconds;           // an idle connection kept open for its next request
  int connections;                     // served at once
};

struct RockingServeConfig {
  const char* host;
  int port;  // 0: a free port
  std::size_t payload_max;  // bytes; no request's body may be larger (413)
  // The largest body a POST to `path` may have (413 beyond it, refused as it
  // arrives, chunked or not); at most payload_max.
  std::size_t (*body_limit)(void* context, const char* path);
  RockingServeLimits limits;
  // The host names the server answers to (a request whose Host header names
  // another is refused: DNS rebinding), each without its port ("localhost",
  // "127.0.0.1", "[::1]"). A request with an Origin header is answered only
  // when it is this server's own origin ("http://" + its Host).
  const char* const* hosts;
  std::size_t host_count;
  const RockingServeFile* files;
  std::size_t file_count;
  void* context;  // passed back to every callback
  // A request under /api/ (GET or POST), answered in JSON. Must not throw.
  void (*answer)(void* context, const char* method, const char* path, const char* body, std::size_t body_size,
                 void* response, RockingRespond respond);
  // Called once the socket is bound, with its port.
  void (*listening)(void* context, int port);
  // Polled about every 100 ms: non-zero stops the server.
  int (*stop_requested)(void* context);
  // A failure the plugin met (its message), for the program's log.
  void (*log_error)(void* context, const char* message);
};

// What rocking_serve returns.
enum RockingServeResult { rocking_serve_stopped = 0, rocking_serve_cannot_bind = 1, rocking_serve_ended = 2 };

// Serves until stop_requested says so; blocks.
using RockingServe = int (*)(const RockingServeConfig* config);
}
