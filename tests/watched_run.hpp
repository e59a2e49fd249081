// One run of a scene as every front end runs it (rocking.run's prepare_run,
// then simulate): rk45 (or the integrator named) at rtol (atol = rtol / 100),
// a history row every 0.01 s, under the scene's excitation or the motions
// given, watched by W (an Observer the test defines).
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>
import rocking.run;

// An observer of every phase change and every history row, with for each
// event the index of the row recorded at it.
struct EventsAndRows : rocking::Observer {
  std::vector<rocking::Event> events;
  std::vector<std::size_t> row_after;
  std::vector<rocking::Response> rows;
  void record(const rocking::Response& r) override { rows.push_back(r); }
  void event(const rocking::Event& e) override {
    events.push_back(e);
    row_after.push_back(rows.size());
  }
};

template <class W>
struct WatchedRun {
  rocking::RunResult result;
  W watch;
};

template <class W>
WatchedRun<W> watched_run(const rocking::Scene& scene, double rtol,
                          std::shared_ptr<const rocking::GroundMotion> motion = nullptr,
                          std::optional<double> duration = std::nullopt, const std::string& integrator = "rk45",
                          std::shared_ptr<const rocking::GroundMotion> vertical = nullptr) {
  rocking::RunSpec spec{.scene = scene};
  spec.motion.given = std::move(motion);
  spec.motion.given_vertical = std::move(vertical);
  spec.solver.integrator = integrator;
  spec.solver.rtol = rtol;
  spec.solver.atol = rtol * 1e-2;
  spec.solver.duration = duration;
  spec.history.every = 0.01;
  const rocking::PreparedRun p = rocking::prepare_run(spec);
  WatchedRun<W> out;
  out.result = rocking::simulate(p.model, p.motion, p.options, &out.watch);
  return out;
}
