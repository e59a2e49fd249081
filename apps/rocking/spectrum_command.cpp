// `rocking spectrum`: the overturning spectrum of a rigid block (or of a rigid
// frame on rocking columns) under pulses, the classic teaching figure, for one
// or more block sizes.
#include "commands.hpp"
#include "run_output.hpp"
#include "stop_signals.hpp"
#include "study_folder.hpp"
#include "log.hpp"
#include <fmt/format.h>
#include <numbers>
#include <fstream>
#include <memory>
#include <sstream>
#include <tuple>
import rocking.errors;
import rocking.study;
import rocking.study_files;
import rocking.plot;

namespace rocking::app {

namespace fs = std::filesystem;

namespace {

struct SpectrumArgs {
  SceneOptions scene;
  std::string pulse = "one-sine";
  std::string sizes = "1,4";
  std::string frequencies = "0.5:10:0.25";
  std::string amplitudes = "0.5:8:0.1";
  int threads = 0;
  std::string out = "out/spectrum";
  std::string formats = "png,pdf,svg";
  bool resume = false;
};

const char* spectrum_header =
    "frequency_ratio,amplitude_ratio,period_s,amplitude_g,overturned,uplift,frequency_ratio_low,"
    "frequency_ratio_high,amplitude_ratio_low,amplitude_ratio_high,period_low_s,period_high_s,amplitude_low_g,"
    "amplitude_high_g\n";

// The outcomes (uplift, overturned) of the points an interrupted spectrum
// wrote to `file` (or its .partial file), each checked against its grid point.
std::vector<std::pair<bool, bool>> resumed_points(const fs::path& file, const std::vector<double>& freqs,
                                                  const std::vector<double>& amps) {
  const fs::path rows = resume_source(file);
  std::vector<std::pair<bool, bool>> out;
  std::ifstream in(rows);
  if (!in) return out;  // this size was not begun
  std::string line;
  if (!std::getline(in, line) || line + "\n" != spectrum_header)
    throw InputError(fmt::format("--resume: {}:1: not a spectrum CSV of this version", rows.string()));
  for (int n = 2; std::getline(in, line) && !in.eof(); ++n) {
    const std::size_t k = out.size();
    std::stringstream ss(line);
    std::vector<std::string> f;
    for (std::string field; std::getline(ss, field, ',');) f.push_back(field);
    if (k >= freqs.size() * amps.size() || f.size() != 14 ||
        f[0] != fmt::format("{:.6g}", freqs[k / amps.size()]) || f[1] != fmt::format("{:.6g}", amps[k % amps.size()]))
      throw InputError(fmt::format("--resume: {}:{}: this row is not point {} of this spectrum's grid", rows.string(), n,
                                   k + 1));
    out.emplace_back(f[5] == "1", f[4] == "1");
  }
  return out;
}

// Refuses, before any run, a grid that is hours of work or whose points are
// pulses no ground motion has: periods from a millisecond to a thousand
// seconds, peaks within max_acceleration_g, through Housner's p and the
// slenderness of each size.
void check_spectrum_grid(const SpectrumArgs& a, const Scene& scene, const std::vector<double>& sizes,
                         const std::vector<double>& freqs, const std::vector<double>& amps) {
  for (double size : sizes)
    if (!(size >= 0.01 && size <= 100))
      throw InputError(fmt::format("--sizes {}: every size factor must be in [0.01, 100] (got {:g})", a.sizes, size));
  // About a millisecond a pulse: a grid beyond this is hours of work.
  const double points = static_cast<double>(freqs.size()) * static_cast<double>(amps.size()) *
                        static_cast<double>(sizes.size());
  if (points > 200000)
    throw InputError(fmt::format("--frequencies {} x --amplitudes {} x --sizes {}: {:.3g} pulses (at most 200000); "
                                 "take coarser grids",
                                 a.frequencies, a.amplitudes, a.sizes, points));
  for (const auto& [flag, text, grid] : {std::tuple{"--frequencies", a.frequencies, &freqs},
                                         std::tuple{"--amplitudes", a.amplitudes, &amps}})
    for (double v : *grid)
      if (!(v > 0 && v <= 1000))
        throw InputError(fmt::format("{} {}: every ratio must be in (0, 1000] (got {:g})", flag, text, v));
  for (double size : sizes) {
    const SpectrumScale scale = spectrum_scale(scene, size);
    const double p = scale.p, tan_alpha = std::tan(scale.alpha);
    const double low = 2 * std::numbers::pi / (1e3 * p), high = 2 * std::numbers::pi / (1e-3 * p);
    for (double f : freqs)
      if (!(f >= low && f <= high))
        throw InputError(fmt::format("--frequencies {}: ratio {:g} is a pulse period of {:.3g} s for this block (size "
                                     "{:g}); the ratios it takes are [{:.3g}, {:.3g}] (periods 1e-3 to 1e3 s)",
                                     a.frequencies, f, 2 * std::numbers::pi / (f * p), size, low, high));
    for (double amp : amps)
      if (!(amp * tan_alpha <= max_acceleration_g))
        throw InputError(fmt::format("--amplitudes {}: ratio {:g} is a pulse of {:.3g} g for this block (size {:g}); "
                                     "the ratios it takes are at most {:.3g} ({:g} g)", a.amplitudes, amp,
                                     amp * tan_alpha, size, max_acceleration_g / tan_alpha, max_acceleration_g));
  }
}

// The rows of spectrum.data/size_X.csv for the points done, and how many of
// them overturn the block.
std::pair<std::string, long> spectrum_rows(const BlockSpectrum& s, const std::vector<double>& freqs,
                                           const std::vector<double>& amps) {
  std::string out = spectrum_header;
  long overturned = 0;
  // Each grid point's cell reaches halfway to its neighbours (as far on the
  // outside), in the normalised axes; in seconds and g through the same map.
  auto cell = [](const std::vector<double>& grid, std::size_t i) {
    const double below = i > 0 ? grid[i] - grid[i - 1] : grid.size() > 1 ? grid[1] - grid[0] : 0.1 * grid[0];
    const double above = i + 1 < grid.size() ? grid[i + 1] - grid[i] : below;
    return std::pair{grid[i] - below / 2, grid[i] + above / 2};
  };
  // In seconds a cell reaches halfway to its neighbours' periods (as far on
  // the outside): mapping the frequency cell instead would stretch the
  // lowest frequencies' cells over many seconds never computed.
  auto period_cell = [&](std::size_t i, double to_period) {
    const auto T = [&](std::size_t j) { return to_period / freqs[j]; };
    const std::size_t n = freqs.size();
    const double longer = i > 0 ? T(i - 1) - T(i) : n > 1 ? T(0) - T(1) : 0.1 * T(0);
    const double shorter = i + 1 < n ? T(i) - T(i + 1) : longer;
    return std::pair{T(i) - shorter / 2, T(i) + longer / 2};
  };
  for (std::size_t k = 0; k < s.complete; ++k) {
    const SpectrumPoint& pt = s.points[k];
    const auto [f_lo, f_hi] = cell(freqs, k / amps.size());
    const auto [a_lo, a_hi] = cell(amps, k % amps.size());
    const double to_period = pt.period_s * pt.frequency_ratio, to_g = pt.amplitude_g / pt.amplitude_ratio;
    const auto [t_lo, t_hi] = period_cell(k / amps.size(), to_period);
    out += fmt::format("{:.6g},{:.6g},{:.6g},{:.6g},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n",
                       pt.frequency_ratio, pt.amplitude_ratio, pt.period_s, pt.amplitude_g, pt.overturned ? 1 : 0,
                       pt.uplift ? 1 : 0, f_lo, f_hi, a_lo, a_hi, t_lo, t_hi, a_lo * to_g,
                       a_hi * to_g);
    overturned += pt.overturned;
  }
  return {out, overturned};
}

int spectrum(const SpectrumArgs& a) {
  SceneOptions opts = a.scene;
  if (opts.path.empty()) opts.path = std::string(ROCKING_SCENES_DIR) + "/rigid_block.toml";
  Scene scene = load_scene(opts);
  if (!scene.structure.rigid) {
    log::info("{}: treated as a rigid block (structure.rigid = true) for the spectrum", scene.source);
    opts.overrides.push_back("structure.rigid=true");
    scene = load_scene(opts);
  }
  const PulseShape shape = parse_pulse_shape(a.pulse);
  const std::vector<double> freqs = number_list("--frequencies", a.frequencies),
                            amps = number_list("--amplitudes", a.amplitudes);
  const std::vector<double> sizes = number_list("--sizes", a.sizes);
  check_spectrum_grid(a, scene, sizes, freqs, amps);
  const int threads = thread_count(a.threads);
  const std::vector<std::string> formats = plot::parse_formats(a.formats);  // refused before any run
  const fs::path dir(a.out);
  make_output_dir(dir / "spectrum.data");
  const FolderLock lock(dir);
  check_outputs_free(dir, {"inputs.txt"});
  record_inputs(dir,
                study_inputs("spectrum", scene_toml(opts.path, opts.overrides), {},
                             {{"pulse", a.pulse}, {"sizes", a.sizes}, {"frequencies", a.frequencies},
                              {"amplitudes", a.amplitudes}}),
                a.resume);
  catch_stop_signals();
  std::vector<plot::Series> series;
  for (double size : sizes) {
    const std::string file = (fs::path("spectrum.data") / fmt::format("size_{}.csv", size)).string();
    const fs::path path = dir / file, partial = path.string() + ".partial";
    check_outputs_free(dir, {file, file + ".partial"});
    const auto done = a.resume ? resumed_points(path, freqs, amps) : std::vector<std::pair<bool, bool>>{};
    Progress progress(log::shows(log::Level::info));
    const BlockSpectrum s = overturning_spectrum(
        scene, size, shape, freqs, amps, threads, [&](std::size_t n, std::size_t total) { progress(n, total); }, done,
        [] { return stop_signal() != 0; });
    const auto [out, overturned] = spectrum_rows(s, freqs, amps);
    std::error_code ec;
    if (s.complete < s.points.size()) {  // stopped: the points done, whole, in the .partial file
      write_text(partial, out);
      const int signal = stop_signal();
      fmt::print(stderr, "rocking: stopped by {} after {} of {} pulses of block x{}; {} holds them; continue with the "
                         "same command and --resume\n",
                 stop_signal_name(signal), s.complete, s.points.size(), size, partial.string());
      return stop_exit_code(signal);
    }
    write_text(path, out);
    fs::remove(partial, ec);
    if (scene.columns)
      fmt::print("frame x{}: {} columns {:.2f} m wide and {:.2f} m tall, p-hat = {:.3f} rad/s, alpha = {:.4f} rad: {} "
                 "of {} pulses overturn it\n",
                 size, scene.columns->count, 2 * scene.columns->half_width * size,
                 2 * scene.columns->half_height * size, s.p, s.alpha, overturned, s.points.size());
    else
      fmt::print("block x{}: {:.2f} m wide, top node at {:.2f} m, p = {:.3f} rad/s, alpha = {:.4f} rad: {} of {} pulses "
                 "overturn it\n",
                 size, 2 * scene.structure.half_width * size, scene.structure.heights.maxCoeff() * size, s.p, s.alpha,
                 overturned, s.points.size());
    series.push_back({fmt::format("block x{} (p = {:.2f} rad/s)", size, s.p), file, {}});
  }
  plot::Figure fig;
  fig.dir = dir;
  fig.name = "spectrum";
  fig.formats = formats;
  fig.width = 1200;
  fig.height = 600;
  fig.title = fmt::format("{}: overturning under {} pulses (filled: overturns)", scene.name, a.pulse);
  for (const fs::path& f : plot::render_spectrum(fig, series, "pulse frequency / p  [-]", "pulse amplitude / (g tan alpha)  [-]"))
    fmt::print("wrote {}\n", f.string());
  return 0;
}

}  // namespace

Command add_spectrum_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "spectrum",
      "Overturning spectrum of a rigid block under one-sine or Ricker pulses:\n"
      "pulse amplitude over g tan(alpha) against pulse frequency over p, shaded\n"
      "where the block overturns; with several --sizes (lengths scaled, the same\n"
      "slenderness) also in seconds and g, which shows Housner's size effect.\n"
      "A flexible scene is made rigid. p = sqrt(m g R / J_p) is Housner's frequency\n"
      "parameter (R from the pivot to the centre of gravity), as `rocking modal` prints.\n"
      "A scene on [columns] gives the rigid frame's spectrum: p is then the frame's\n"
      "p-hat, p^2 (1 + 2 gamma) / (1 + 3 gamma), and alpha its columns' (MODEL.md 16);\n"
      "--sizes scales the columns with the structure.\n"
      "Ctrl-C or SIGTERM stops it with the pulses done kept (exit 130 / 143);\n"
      "--resume continues.");
  auto a = std::make_shared<SpectrumArgs>();
  add_scene_options(*cmd, a->scene, "data/scenes/rigid_block.toml");
  cmd->add_option("--pulse", a->pulse, "one-sine (default) or ricker")->type_name("SHAPE");
  cmd->add_option("--sizes", a->sizes, "Block size factors (default 1,4)")->type_name("LIST");
  cmd->add_option("--frequencies", a->frequencies, "omega_p / p grid (default 0.5:10:0.25)")->type_name("SPEC");
  cmd->add_option("--amplitudes", a->amplitudes, "a_p / (g tan alpha) grid (default 0.5:8:0.1)")->type_name("SPEC");
  cmd->add_option("--threads", a->threads, "Worker threads (default: every core)")->type_name("N");
  cmd->add_option("--out", a->out, "Output folder (default out/spectrum)")->type_name("DIR");
  cmd->add_option("--formats", a->formats, "Figure formats (default png,pdf,svg)")->type_name("LIST");
  cmd->add_flag("--resume", a->resume,
                "Continue a spectrum stopped by Ctrl-C or SIGTERM in the same --out, with the\n"
                "same inputs (DIR/inputs.txt): the pulses done are kept");
  cmd->footer("Example: rocking spectrum --pulse ricker --sizes 1,2,4 --out plots/spectrum");
  return [a]() { return spectrum(*a); };
}

}  // namespace rocking::app
