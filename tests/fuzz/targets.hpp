// The fuzz targets: every reader and parser a user's bytes reach, each as a
// function of the bytes that must either succeed or throw InputError, never
// crash, hang, leak or throw anything else. tests/fuzz/*_fuzz.cpp hand them to
// libFuzzer (`make fuzz`); tests/fuzz_replay_test.cpp replays the committed
// corpus and the regression inputs through them on every `make test`.
// Include after <rocking/eigen.hpp> and before any import.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>
#include <nlohmann/json.hpp>
#include <unistd.h>
import rocking.scene;
import rocking.study;
import rocking.study_files;
import rocking.fitting;
import rocking.modal;
import rocking.intensity;
import rocking.sundials;
import rocking.plot;
import rocking.errors;
import rocking.lab;
import rocking.records;

namespace fuzz {

// The bytes as a file of this process's own (readers take paths).
inline std::string as_file(const std::uint8_t* data, std::size_t size, const char* name) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("rocking_fuzz_" + std::to_string(::getpid()) + "_" + name)).string();
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

// Runs f, accepting success or InputError: anything else escapes to the fuzzer.
template <class F>
void input_or_error(F&& f) {
  try {
    f();
  } catch (const rocking::InputError&) {
  }
}

// A record file of any format, detected from its content.
inline void record(const std::uint8_t* data, std::size_t size) {
  const std::string path = as_file(data, size, "record");
  input_or_error([&] { (void)rocking::read_record(path); });
  input_or_error([&] {  // the one-column reading, which needs --dt
    rocking::RecordOptions o;
    o.dt = 0.01;
    (void)rocking::read_record(path, o);
  });
  std::remove(path.c_str());
}

// A scene file: TOML, then the schema and every value's check.
inline void scene(const std::uint8_t* data, std::size_t size) {
  const std::string path = as_file(data, size, "scene.toml");
  input_or_error([&] { (void)rocking::load_scene(path); });
  std::remove(path.c_str());
}

// The scene's model and its linearisation, which must be finite for any
// scene its checks let through.
inline void model_and_modes(const rocking::Scene& scene) {
  (void)rocking::make_contact_model(scene, true);
  const rocking::ModalSummary m = rocking::modal_analysis(scene.structure, rocking::scene_devices(scene));
  for (double v : {m.rocking_p, m.damper_pre_yield_hz, m.damper_post_yield_p, m.devices[0].at_rest, m.devices[1].at_rest,
                   m.devices[0].held_moment, m.devices[1].held_moment, m.J_p, m.alpha_cg})
    if (!std::isfinite(v)) __builtin_trap();
}

// One --set TABLE.KEY=VALUE on the built-in chimney.
inline void set_override(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  input_or_error([&] { model_and_modes(rocking::load_default_scene({text})); });
}

// --scales, --levels, --sizes, --rtols: FIRST:LAST:STEP or a comma list.
// Accepted lists are finite values, at most a million and one of them.
inline void number_list(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  input_or_error([&] {
    const std::vector<double> v = rocking::parse_number_list(text);
    if (v.empty() || v.size() > 1000001) __builtin_trap();
    for (double x : v)
      if (!std::isfinite(x)) __builtin_trap();
  });
}

// A history.csv read back by `plot response --from` (rocking.plot's
// check_history): accepted only as whole rows of finite numbers (or empty
// fields, or the phase's labels) under a header with a drift column.
inline void history_csv(const std::uint8_t* data, std::size_t size) {
  const std::string path = as_file(data, size, "history.csv");
  input_or_error([&] {
    const rocking::plot::HistoryContent c = rocking::plot::check_history(path);
    if (c.columns.empty() || c.column("delta_t") == 0) __builtin_trap();
  });
  std::remove(path.c_str());
}

// An ida.csv read back by --resume (rocking.study_files' read_resumed_rows)
// for a study of the built-in chimney under a short pulse-like record, two
// variants at three levels: only rows of its jobs, in order, are kept, and
// every kept row's numbers are finite.
inline void study_csv(const std::uint8_t* data, std::size_t size) {
  struct Fixture {
    std::unique_ptr<rocking::Study> study;
    std::vector<rocking::Job> jobs;
    std::vector<std::string> ids;
    rocking::StudyColumns columns;
  };
  static const Fixture f = [] {
    std::vector<double> t, a;
    for (int i = 0; i <= 100; ++i) {
      t.push_back(0.01 * i);
      a.push_back(0.3 * 9.81 * std::sin(0.2 * i));
    }
    const auto motion = std::make_shared<const rocking::GroundMotion>(
        rocking::GroundMotion::from_samples("fuzz.at2", t, a));
    Fixture x;
    x.study = std::make_unique<rocking::Study>(
        "", std::vector<std::string>{}, std::vector<rocking::StudyRecord>{{"fuzz.at2", motion}}, rocking::RecordOptions{},
        std::vector<rocking::Variant>{rocking::named_variant("damper"), rocking::named_variant("no-damper")},
        rocking::RunOptions{});
    x.jobs = x.study->ladder({1, 2, 3});
    x.ids = rocking::record_ids(x.study->records());
    x.columns = rocking::study_columns(*x.study);
    return x;
  }();
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  input_or_error([&] {
    const rocking::ResumedRows r = rocking::read_resumed_rows(in, "ida.csv", f.jobs, f.ids, *f.study, f.columns);
    if (r.rows.size() > f.jobs.size() || r.results.size() != r.rows.size()) __builtin_trap();
    for (std::size_t k = 0; k < r.results.size(); ++k) {
      const rocking::StudyRow& row = r.results[k];
      if (row.level != f.jobs[k].level || (row.ran && row.values.size() != f.columns.size())) __builtin_trap();
      for (double v : row.values)
        if (!std::isnan(v) && !std::isfinite(v)) __builtin_trap();
    }
  });
}

// --process SPEC: parsed, and when accepted applied to a short record, whose
// processed samples must be finite.
inline void processing(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  input_or_error([&] {
    const rocking::Processing p = rocking::parse_processing(text);
    std::vector<double> a(400);
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = std::sin(0.37 * static_cast<double>(i)) + 1e-3 * static_cast<double>(i);
    const rocking::GroundMotion g = rocking::process(rocking::GroundMotion::evenly_sampled("fuzz", 0.01, a), p);
    for (double v : g.sample_values())
      if (!std::isfinite(v)) __builtin_trap();
  });
}

// A request to the browser lab's API (rocking.lab): the first byte picks the
// endpoint, the rest is the body. The dispatcher answers every body with a
// status (never throws): an upload is read by the record readers; a simulate
// request is read and checked (the scene
// loaded with its overrides, the record read) but not run, so that the
// fuzzer spends its time on the parsing; modal requests run (they are cheap).
inline void lab_request(const std::uint8_t* data, std::size_t size) {
  static const rocking::Lab lab({.scenes = std::string(ROCKING_SOURCE_DIR) + "/data/scenes",
                                 .records = std::string(ROCKING_SOURCE_DIR) + "/../shared/data/records"});
  if (size == 0) return;
  const std::string body(reinterpret_cast<const char*>(data) + 1, size - 1);
  static constexpr const char* paths[] = {"/api/modal", "/api/scenes", "/api/nothing", "/api/upload", "/api/simulate"};
  const char* path = paths[data[0] % 5];
  if (path != paths[4]) {
    const rocking::LabAnswer a = lab.answer(data[0] & 4 ? "GET" : "POST", path, body);
    if (a.status < 200 || a.status >= 500 || a.body.empty()) __builtin_trap();
    return;
  }
  const nlohmann::json request = nlohmann::json::parse(body, nullptr, false);
  if (request.is_discarded()) return;
  input_or_error([&] { (void)lab.read_simulate(request); });
}

// A cyclic test table (rocking fit): read, and when short, fitted (a fit
// that does not converge on such bytes is a RunError, which is refused too).
inline void cyclic_test(const std::uint8_t* data, std::size_t size) {
  const std::string path = as_file(data, size, "cyclic.csv");
  input_or_error([&] {
    const rocking::CyclicTest test = rocking::read_cyclic_test(path);
    if (test.e.size() <= 60) {
      try {
        (void)rocking::fit_law(test, {"bouc-wen", {{"n", 1.0}}});
      } catch (const rocking::RunError&) {
      }
    }
  });
  std::remove(path.c_str());
}

// One key of one [[device]] on the built-in chimney: the first byte picks a
// registered law, the second one of the keys a device of it reads, the rest is
// that key's value (the others hold values the law takes). Through the
// scene's checks, the model and its linearisation, which must be finite.
inline void device_set(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return;
  const std::vector<rocking::LawInfo> laws = rocking::device_laws();
  const rocking::LawInfo& law = laws[data[0] % laws.size()];
  std::vector<std::string> keys{"at", "kinematics", "free_length", "capacity", "name"};
  for (const rocking::LawParameter& p : law.parameters) keys.push_back(p.key);
  const std::string& key = keys[data[1] % keys.size()];
  const std::string value(reinterpret_cast<const char*>(data + 2), size - 2);
  std::string table = "device+={kind=\"" + law.name + "\"";
  if (key != "at") table += ", at=\"edges\"";
  for (const rocking::LawParameter& p : law.parameters) {
    if (p.key == key) continue;
    const bool fine = rocking::within(p, p.default_value);
    table += ", " + p.key + "=" + std::to_string(fine ? p.default_value : std::fmin(p.maximum, std::fmax(1.0, 2 * p.minimum)));
  }
  table += ", " + key + "=" + value + "}";
  input_or_error([&] { model_and_modes(rocking::load_default_scene({table})); });
}

// The parsers behind the subcommands' option values: the first byte picks
// one (--im, --limit, --integrator, --units, --pulse, --formats, --size,
// --variants), the rest is the value.
inline void option_value(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  input_or_error([&] {
    switch (data[0] % 8) {
      case 5: (void)rocking::plot::parse_formats(text); break;
      case 6: {
        const auto [w, h] = rocking::plot::parse_size(text, 200, 200, 10000);
        if (w < 200 || h < 200 || w > 10000 || h > 10000) __builtin_trap();
        break;
      }
      case 7: (void)rocking::named_variant(text); break;
      case 0: {
        const rocking::IntensityMeasure im = rocking::parse_intensity_measure(text, 0.05, 0.46);
        if (!std::isfinite(im.t1)) __builtin_trap();
        break;
      }
      case 1: (void)rocking::parse_limit(text); break;
      case 2: (void)rocking::ode::parse_backend(text); break;
      case 3: (void)rocking::parse_acceleration_unit(text); break;
      case 4: (void)rocking::parse_pulse_shape(text); break;
    }
  });
}

}  // namespace fuzz
