// `rocking record`: what a ground motion is, in the measures of the field
// (MODEL.md 12): PGA, PGV, PGD, Arias intensity, D5-95, CAV and the
// pseudo-spectral acceleration at chosen periods, for records in any format
// the readers know; figures of the records and their spectra; RotD50 and
// RotD100 of a record's two horizontal components (MODEL.md 14).
#include "commands.hpp"
#include "run_output.hpp"
#include <nlohmann/json.hpp>
#include "log.hpp"
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
import rocking.study_files;
import rocking.errors;
import rocking.plot;
import rocking.records;

namespace rocking::app {

namespace fs = std::filesystem;

namespace {

struct RecordArgs {
  std::vector<std::string> files;
  RecordFileOptions file;
  std::string periods;
  double damping = 0.05;
  bool json = false;
  std::string out;
  std::string formats = "png,pdf,svg";
  bool log_axes = false;
  std::string window;
  std::string scene;
  std::vector<std::string> overrides;
  bool rotd = false;
  std::string second;  // the other horizontal component's file
};

struct Measured {
  std::string id, path;
  GroundMotion motion;
  RecordMeasures m;
  std::vector<RotD> rotd;  // empty: not asked for
};

// One column per record, one row per measure.
void print_table(const std::vector<Measured>& rs) {
  std::size_t width = 12;
  for (const Measured& r : rs) width = std::max(width, r.id.size() + 2);
  const std::size_t name = 18;
  auto row = [&](const std::string& label, auto cell) {
    std::string line = fmt::format("{:<{}}", label, name);
    for (const Measured& r : rs) line += fmt::format("{:<{}}", cell(r), width);
    while (!line.empty() && line.back() == ' ') line.pop_back();
    fmt::print("{}\n", line);
  };
  row("record", [](const Measured& r) { return r.id; });
  for (const Measured& r : rs)
    if (const std::string label = r.motion.info().label(); !label.empty()) fmt::print("  {}: {}\n", r.id, label);
  row("format", [](const Measured& r) {
    return r.motion.info().format + (r.motion.info().component.empty() ? "" : " " + r.motion.info().component);
  });
  row("samples", [](const Measured& r) {
    const double dt = r.motion.info().dt;
    return dt > 0 ? fmt::format("{} x {:g} s", r.motion.sample_count(), dt) : fmt::format("{} (uneven)", r.motion.sample_count());
  });
  row("duration [s]", [](const Measured& r) { return fmt::format("{:.2f}", r.motion.duration()); });
  row("PGA [g]", [](const Measured& r) { return fmt::format("{:.4f} @{:.2f}s", r.m.pga / gravity, r.m.pga_time); });
  row("PGV [m/s]", [](const Measured& r) { return fmt::format("{:.4f}", r.m.pgv); });
  row("PGD [m]", [](const Measured& r) { return fmt::format("{:.4f}", r.m.pgd); });
  row("Arias [m/s]", [](const Measured& r) { return fmt::format("{:.4f}", r.m.arias); });
  row("D5-95 [s]", [](const Measured& r) { return fmt::format("{:.2f}", r.m.d5_95); });
  row("CAV [m/s]", [](const Measured& r) { return fmt::format("{:.3f}", r.m.cav); });
  fmt::print("PSA, {:g} % damped [g]\n", 100 * rs.front().m.damping);
  for (std::size_t k = 0; k < rs.front().m.periods.size(); ++k)
    row(fmt::format("  T = {:g} s", rs.front().m.periods[k]),
        [&](const Measured& r) { return fmt::format("{:.4f}", r.m.psa[k] / gravity); });
  if (rs.front().rotd.empty()) return;
  row("RotD of", [](const Measured& r) {
    const GroundMotion* o = r.motion.other_horizontal();
    return fmt::format("{}+{}", r.motion.info().component, o->info().component);
  });
  fmt::print("RotD50 / RotD100, {:g} % damped [g]\n", 100 * rs.front().m.damping);
  for (std::size_t k = 0; k < rs.front().m.periods.size(); ++k)
    row(fmt::format("  T = {:g} s", rs.front().m.periods[k]), [&](const Measured& r) {
      return fmt::format("{:.4f} {:.4f}", r.rotd[k].rotd50 / gravity, r.rotd[k].rotd100 / gravity);
    });
}

// A record in a figure's key: its station and component where the file
// names them (else its event, else its id), with the event when it fits.
std::string key_label(const Measured& r) {
  constexpr std::size_t room = 72;
  const RecordInfo& i = r.motion.info();
  std::string label = !i.station.empty() ? i.station + (i.component.empty() ? "" : ", " + i.component)
                      : !i.event.empty() ? i.event
                                         : r.id;
  if (!i.station.empty() && !i.event.empty() && label.size() + i.event.size() + 3 <= room)
    label += " (" + i.event + ")";
  return label.size() > room ? label.substr(0, room - 3) + "..." : label;
}

void write_figures(const RecordArgs& a, const std::vector<Measured>& rs, const std::vector<plot::Mark>& marks,
                   const std::string& scene_name) {
  const fs::path dir(a.out);
  make_output_dir(dir / "record.data");
  const std::vector<double> dense = log_periods(0.01, 10.0, 120);
  std::vector<plot::Series> histories, spectra;
  std::string table = "id,period_s,psa_g\n";
  for (std::size_t i = 0; i < rs.size(); ++i) {
    const Measured& r = rs[i];
    const GroundHistory h = integrate_record(r.motion);
    std::string csv = "t_s,a_g,v_m_s,d_m\n";
    for (std::size_t k = 0; k < h.t.size(); ++k)
      csv += fmt::format("{:.9g},{:.9g},{:.9g},{:.9g}\n", h.t[k], h.a[k] / gravity, h.v[k], h.d[k]);
    const std::string stem = fmt::format("record_{}", i + 1);
    write_text(dir / "record.data" / (stem + ".csv"), csv);
    const std::vector<double> psa = response_spectrum(r.motion, dense, a.damping);
    std::string sp = "period_s,psa_g\n";
    for (std::size_t k = 0; k < dense.size(); ++k) {
      sp += fmt::format("{:.9g},{:.9g}\n", dense[k], psa[k] / gravity);
      table += fmt::format("{},{:.9g},{:.9g}\n", r.id, dense[k], psa[k] / gravity);
    }
    write_text(dir / "record.data" / (stem + "_spectrum.csv"), sp);
    const std::string label = key_label(r);
    plot::Series s;
    s.label = label;
    s.file = (fs::path("record.data") / (stem + ".csv")).string();
    s.points = false;
    histories.push_back(s);
    s.file = (fs::path("record.data") / (stem + "_spectrum.csv")).string();
    spectra.push_back(s);
  }
  write_text(dir / "spectrum.csv", table);
  const std::vector<std::string> formats = plot::parse_formats(a.formats);
  plot::Figure fig;
  fig.dir = dir;
  fig.formats = formats;
  fig.name = "record";
  fig.title = rs.size() == 1 ? fmt::format("{}", rs.front().id) : fmt::format("{} records", rs.size());
  fig.height = 1100;
  std::vector<const GroundMotion*> motions;
  for (const Measured& r : rs) motions.push_back(&r.motion);
  const std::string window = window_range(a.window, motions);
  std::vector<std::filesystem::path> written = plot::render_panels(
      fig, 3, 1, "time t [s]",
      {plot::Panel{"ground acceleration a_g [g]", plot::column("t_s"), plot::column("a_g"), false, "", {}, window},
       plot::Panel{"ground velocity v_g [m/s]", plot::column("t_s"), plot::column("v_m_s"), false, "", {}, window},
       plot::Panel{"ground displacement d_g [m]", plot::column("t_s"), plot::column("d_m"), false, "", {}, window}},
      histories);
  fig.name = "spectrum";
  fig.title = fmt::format("Pseudo-spectral acceleration, {:g} % damped{}", 100 * a.damping,
                          marks.empty() ? "" : fmt::format("\ndashed: the fixed-base periods of {}", scene_name));
  fig.height = 800;
  const auto more = plot::render_panels(fig, 1, 1, "T [s]", {plot::Panel{"PSA [g]", plot::column("period_s"), plot::column("psa_g"), !a.log_axes, "", marks}},
                                        spectra, a.log_axes);
  written.insert(written.end(), more.begin(), more.end());
  for (const auto& f : written) log::info("wrote {}", f.string());
  log::info("wrote {} (the spectrum at {} periods from 0.01 to 10 s)", (dir / "spectrum.csv").string(), dense.size());
}

// The scene's fixed-base periods (at most three), to mark on the spectrum.
std::vector<plot::Mark> scene_periods(const RecordArgs& a, std::string& scene_name) {
  if (a.scene.empty() && a.overrides.empty()) return {};
  const Scene scene = load_scene(SceneOptions{a.scene, a.overrides});
  scene_name = scene.name;
  if (scene.structure.rigid) {
    log::info("{}: a rigid block has no fixed-base periods to mark", scene.source);
    return {};
  }
  const ModalSummary m = modal_analysis(scene.structure, scene_devices(scene));
  std::vector<plot::Mark> marks;
  for (std::size_t i = 0; i < m.fixed_base_hz.size() && i < 3; ++i) {
    const double T = 1.0 / m.fixed_base_hz[i];
    if (T >= 0.01 && T <= 10) marks.push_back({T, fmt::format("T{} = {:.3f} s", i + 1, T)});
  }
  return marks;
}

int record(const RecordArgs& a) {
  if (!(a.damping >= 0 && a.damping < 1)) throw InputError(fmt::format("--damping {}: must be in [0, 1)", a.damping));
  const std::vector<double> periods = a.periods.empty() ? standard_periods() : number_list("--periods", a.periods);
  if (periods.size() > 10000)
    throw InputError(fmt::format("--periods {}: {} periods (at most 10000)", a.periods, periods.size()));
  for (double T : periods) try {
      check_period(T);
    } catch (const InputError& e) {
      throw InputError(fmt::format("--periods {}: {}", a.periods, e.what()));
    }
  if (!a.out.empty()) plot::parse_formats(a.formats);  // refused before any work
  if (!a.window.empty() && a.out.empty()) throw InputError("--window: shapes the figures of --out; give --out DIR");
  if (a.window != "auto") window_range(a.window, {});  // T0:T1 refused before any work
  std::string scene_name;
  const std::vector<plot::Mark> marks = scene_periods(a, scene_name);
  RecordOptions ro = record_options(a.file);
  ro.read_as = ReadAs::any;  // measured, whichever its direction
  const std::vector<std::string> ids = record_ids(a.files);
  std::vector<Measured> rs;
  if (!a.second.empty() && (!a.rotd || a.files.size() != 1))
    throw InputError("--second: the other horizontal component of one record, for --rotd");
  // --rotd: each record with its other horizontal component (its file's, or --second).
  ro.other_horizontal = a.rotd && a.second.empty();
  // --process: each record as recorded, then processed, side by side.
  RecordOptions raw = ro;
  raw.process = {};
  const bool processed = ro.process.any();
  for (std::size_t i = 0; i < a.files.size(); ++i)
    for (const RecordOptions* options : processed ? std::vector{&raw, &ro} : std::vector{&ro}) {
      GroundMotion g = read_record(a.files[i], *options);
      if (!a.second.empty()) {
        RecordOptions other = *options;
        other.read_as = ReadAs::horizontal;
        other.component.clear();
        other.other_horizontal = false;
        g = g.with_other_horizontal(read_record(a.second, other));
      }
      RecordMeasures m = measure_record(g, periods, a.damping);
      std::vector<RotD> rotd = a.rotd ? rotd_spectrum(g, *g.other_horizontal(), periods, a.damping) : std::vector<RotD>{};
      const std::string id = options == &ro && processed ? ids[i] + " processed" : ids[i];
      rs.push_back({id, a.files[i], std::move(g), std::move(m), std::move(rotd)});
    }
  nlohmann::json all = nlohmann::json::array();
  for (const Measured& r : rs) {
    nlohmann::json j = record_summary(r.id, r.path, r.motion, r.m);
    if (!r.rotd.empty()) {
      std::vector<double> r50, r100;
      for (const RotD& x : r.rotd) {
        r50.push_back(x.rotd50 / gravity);
        r100.push_back(x.rotd100 / gravity);
      }
      j["rotd_components"] = {r.motion.info().component, r.motion.other_horizontal()->info().component};
      j["rotd50_g"] = r50;
      j["rotd100_g"] = r100;
    }
    all.push_back(std::move(j));
  }
  if (a.json) std::cout << all.dump(2) << '\n';
  else print_table(rs);
  if (!a.out.empty()) {
    write_figures(a, rs, marks, scene_name);
    write_text(fs::path(a.out) / "record.json", all.dump(2) + "\n");
  }
  return 0;
}

}  // namespace

Command add_record_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "record",
      "What a ground motion is: PGA, PGV, PGD, Arias intensity, D5-95, CAV and\n"
      "the pseudo-spectral acceleration PSA(T) (MODEL.md 12), for records in any\n"
      "format below, side by side. Velocity and displacement are the exact\n"
      "integrals of the piecewise-linear record from rest (no baseline\n"
      "correction); PSA is exact between samples, its peak located between them.");
  auto a = std::make_shared<RecordArgs>();
  cmd->add_option("files", a->files, "Record files (any format --format lists)")->required()->type_name("FILE...");
  add_record_file_options(*cmd, a->file);
  cmd->add_option("--periods", a->periods,
                  "Periods of the PSA table: FIRST:LAST:STEP or a list 0.2,0.5,1\n"
                  "(default the 21 of NGA-West2 from 0.01 to 10 s)")
      ->type_name("LIST");
  cmd->add_option("--damping", a->damping, "Damping ratio of the spectrum (default 0.05)")->type_name("ZETA");
  cmd->add_flag("--json", a->json,
                "Print a JSON array, one object per record: metadata, pga_g, pgv_m_s,\n"
                "pgd_m, arias_m_s, d5_95_s, cav_m_s, periods_s, psa_g (SI units, g)");
  cmd->add_option("--out", a->out,
                  "Write figures (record: a, v, d; spectrum: PSA against T), the data\n"
                  "behind them and record.json to DIR")
      ->type_name("DIR");
  cmd->add_option("--formats", a->formats, "Figure formats: png,pdf,svg (default all)")->type_name("LIST");
  cmd->add_flag("--log", a->log_axes, "Spectrum on log-log axes");
  add_window_option(*cmd, a->window);
  cmd->add_flag("--rotd", a->rotd,
                "RotD50 and RotD100 at the periods (Boore 2010: the median and the\n"
                "largest PSA over the azimuths 0-179 degrees of the two horizontal\n"
                "components; MODEL.md 14), of each record with the other horizontal\n"
                "component its file holds (GeoNet), or with --second");
  cmd->add_option("--second", a->second,
                  "The other horizontal component's file, for --rotd of one record (a PEER pair)")
      ->type_name("FILE");
  cmd->add_option("--scene", a->scene,
                  "Mark this scene's fixed-base periods on the spectrum (--set applies)")
      ->type_name("SCENE");
  cmd->add_option("--set", a->overrides, "Override a value of --scene, TABLE.KEY=VALUE (repeatable)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  cmd->footer(
      "Examples:\n"
      "  rocking record ../shared/data/records/elcentro_1940_ns.at2\n"
      "  rocking record ../shared/data/records/formats/20161113_110259_WTMC_20.V2A --component Up --json\n"
      "  rocking record a.at2 b.V2A --out out/records --log --scene data/scenes/christchurch_chimney.toml\n"
      "  rocking record ../shared/data/records/formats/20161113_110259_WTMC_20.V2A --rotd\n"
      "  rocking record ../shared/data/records/christchurch2011_cbgs_n89w.at2 --rotd\n"
      "      --second ../shared/data/records/christchurch2011_cbgs_s01w.at2\n"
      "  rocking record ../shared/data/records/formats/20161113_110259_WTMC_20.V2A --out out/waiau --window auto");
  return [a]() { return record(*a); };
}

}  // namespace rocking::app
