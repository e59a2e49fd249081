// `rocking animate`: an animated GIF (gnuplot's gif animate terminal) of the
// structure drawn to scale, rocking about its pivots with its lifted edge and
// stretched damper, beside its twin (fixed base, or without a device) under the same
// record, with a moving cursor on the ground-motion and base-moment traces.
#include "commands.hpp"
#include "run_output.hpp"
#include "stop_signals.hpp"
#include <spdlog/spdlog.h>
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <numbers>

namespace rocking::app {

namespace fs = std::filesystem;

namespace {

struct AnimateArgs {
  SceneOptions scene;
  MotionOptions motion;
  SolverOptions solver;
  std::string compare;  // empty: fixed-base, or none for a rigid block
  std::string out = "out/animation.gif";
  double speed = 1.0;
  int max_frames = 240;
  int fps = 20;
  double exaggeration = 0;  // 0: automatic
  double rotation = 0;      // rocking angle drawn x this; 0: automatic
  std::string size = "1000x700";
  std::string window;   // --window: the span animated (empty: the whole run)
};

// Keeps the frames: the response and the elastic displacements at each.
struct FrameRecorder : Observer {
  double interval;
  std::vector<Response> rows;
  std::vector<Eigen::VectorXd> u;
  Eigen::VectorXd next_u;  // the displacements of the row about to be recorded
  explicit FrameRecorder(double dt) : interval(dt) {}
  void record(const Response& r) override {
    // Keep the grid rows only (event rows fall between them).
    const double k = r.t / interval;
    if (std::abs(k - std::round(k)) < 1e-6 && (rows.empty() || r.t > rows.back().t)) {
      rows.push_back(r);
      u.push_back(next_u);
    }
  }
  void nodal(Eigen::Ref<const Eigen::VectorXd> v, Eigen::Ref<const Eigen::VectorXd>) override { next_u = v; }
};

double nice(double x) {  // 1, 2 or 5 x 10^k, not above x
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * p <= x) return m * p;
  return p;
}

// Every m-th recorded row is a frame.
void write_frames(const fs::path& file, const Structure& s, const FrameRecorder& rec, double k, double kr, int m,
                  std::size_t frames, bool has_damper) {
  const char* damper = has_damper ? " 1\n" : " 2\n";  // 2: not drawn
  std::ofstream out(file);
  out << "# one block per frame (index i), each under its header: the axis, the base, the damper; part 1 for the "
         "damper, 2 for none drawn\n";
  for (std::size_t f = 0; f < frames; ++f) {
    out << "x y part\n";
    const std::size_t i = f * static_cast<std::size_t>(m);
    const Response& r = rec.rows[i];
    const Eigen::VectorXd u = i < rec.u.size() ? rec.u[i] : Eigen::VectorXd();
    const Outline o = outline(s, r.phase, kr * r[Quantity::theta], u, k);
    for (const Point& p : o.axis) out << p.first << ' ' << p.second << " 0\n";
    out << '\n' << o.left_corner.first << ' ' << o.left_corner.second << " 0\n"
        << o.right_corner.first << ' ' << o.right_corner.second << " 0\n\n"
        << o.damper_anchor.first << ' ' << o.damper_anchor.second << damper
        << o.damper_end.first << ' ' << o.damper_end.second << damper << "\n\n";
  }
}

int animate(const AnimateArgs& a) {
  const fs::path gif(a.out);
  const std::string ext = gif.extension().string();
  if (ext != ".gif" && ext != ".mp4" && ext != ".webm")
    throw InputError(fmt::format("--out {}: write .gif, or .mp4 / .webm (with ffmpeg)", a.out));
  const bool video = ext != ".gif";
  const std::string ffmpeg = video ? plot::find_program("ffmpeg") : "";
  if (video && ffmpeg.empty())
    throw InputError(fmt::format("--out {}: MP4 and WebM need ffmpeg, which is not installed (apt install ffmpeg); "
                                 "write a .gif instead", a.out));
  if (!(a.speed > 0)) throw InputError(fmt::format("--speed {}: must be positive", a.speed));
  if (a.max_frames < 2 || a.max_frames > 2000) throw InputError(fmt::format("--frames {}: must be 2 to 2000", a.max_frames));
  const auto [width, height] = plot::parse_size(a.size, 300, 200, 4000);
  for (const auto& [value, flag] : {std::pair{a.exaggeration, "--exaggerate"}, std::pair{a.rotation, "--exaggerate-rotation"}})
    if (!std::isfinite(value) || value < 0)
      throw InputError(fmt::format("{} {}: must be a positive number (0: automatic)", flag, value));
  if (a.fps < 1 || a.fps > 100) throw InputError(fmt::format("--fps {}: must be 1 to 100", a.fps));
  const Scene scene = load_scene(a.scene);
  const GroundMotion motion = load_motion(scene, a.motion);
  // A rigid block has no fixed-base twin worth drawing: by default it is drawn alone.
  const std::string compare = !a.compare.empty() ? a.compare : scene.structure.rigid ? "none" : "fixed-base";
  if (compare != "fixed-base" && compare != "no-damper" && compare != "none" && !compare.starts_with("without:"))
    throw InputError(fmt::format("--compare {}: choose fixed-base, without:NAME (a device the scene names), no-damper "
                                 "or none", compare));
  const bool alone = compare == "none";
  std::vector<std::string> twin_overrides = a.scene.overrides;
  if (!alone) {
    const Variant twin_variant = named_variant(compare);
    twin_overrides.insert(twin_overrides.end(), twin_variant.overrides.begin(), twin_variant.overrides.end());
  }
  const Scene twin = load_scene(SceneOptions{a.scene.path, twin_overrides});
  // Both runs as `rocking simulate` makes them (rocking.run), under the motion
  // read once; the frames read no energy.
  auto prepared = [&](const Scene& s, double every) {
    PreparedRun run = prepare_run({.scene = s,
                                   .motion = a.motion,
                                   .solver = a.solver,
                                   .history = {.columns = {}, .every = every},
                                   .track_energy = false},
                                  motion);
    // Ctrl-C or SIGTERM ends the runs within a step and gnuplot within 20 ms;
    // no animation cut short is left under its name (main exits 130 or 143).
    run.options.stop = [] { return stop_signal() != 0; };
    return run;
  };
  catch_stop_signals();
  const RunOptions ro = prepared(scene, 0.01).options;  // the duration, checked
  const double duration = ro.duration > 0 ? ro.duration : motion.duration();
  // The span animated: --window (the run computes from t = 0 all the same).
  const auto window = time_window(a.window, {&motion});
  const double shown_from = window ? std::min((*window)[0], duration) : 0.0,
               shown_to = window ? std::min((*window)[1], duration) : duration;
  if (!(shown_to > shown_from))
    throw InputError(fmt::format("--window {}: the run ends at {:g} s", a.window, duration));
  // At least two frames over the span shown: one per frame interval speed / fps.
  if (!(a.speed <= (shown_to - shown_from) * a.fps))
    throw InputError(fmt::format("--speed {:g}: at most {:.4g} (two frames over the {:g} s shown at {} fps)", a.speed,
                                 (shown_to - shown_from) * a.fps, shown_to - shown_from, a.fps));
  // Frame times: real time / speed at fps, at most max_frames over the span shown.
  double frame_dt = a.speed / a.fps;
  if ((shown_to - shown_from) / frame_dt + 1 > a.max_frames) frame_dt = (shown_to - shown_from) / (a.max_frames - 1);
  // The traces are sampled more finely than the frames: every frame is every m-th row.
  const int m = std::max(1, static_cast<int>(std::ceil(frame_dt / 0.01 - 1e-9)));
  const PreparedRun main_run = prepared(scene, frame_dt / m), twin_run = prepared(twin, frame_dt / m);
  const ContactModel &main_model = main_run.model, &twin_model = twin_run.model;
  FrameRecorder main_rec(main_run.options.output_interval), twin_rec(twin_run.options.output_interval);
  const RunResult r1 = simulate(main_model, main_run.motion, main_run.options, &main_rec);
  const RunResult r2 = simulate(twin_model, twin_run.motion, twin_run.options, &twin_rec);
  for (const RunResult* r : {&r1, &r2})
    if (r->outcome == Outcome::failed) throw RunError(r->failure);
  const std::size_t rows = std::min(main_rec.rows.size(), twin_rec.rows.size());
  const std::size_t frames = (rows + static_cast<std::size_t>(m) - 1) / static_cast<std::size_t>(m);
  const std::size_t first_frame = static_cast<std::size_t>(std::ceil(shown_from / frame_dt - 1e-9));
  const std::size_t last_frame =
      std::min(frames, static_cast<std::size_t>(std::floor(shown_to / frame_dt + 1e-9)) + 1) - 1;
  if (frames < 2 || last_frame < first_frame + 1) throw InputError("animation: the span shown is too short for two frames");
  const double H = scene.structure.heights.maxCoeff(), B = scene.structure.half_width;
  double top = 1e-12;
  for (const Response& r : main_rec.rows) top = std::max(top, std::abs(r[Quantity::u_top]));
  for (const Response& r : twin_rec.rows) top = std::max(top, std::abs(r[Quantity::u_top]));
  const double k = a.exaggeration > 0 ? a.exaggeration : scene.structure.rigid ? 1.0 : std::max(1.0, nice(0.08 * H / top));
  // The rocking of a tall structure is invisible at true scale: by default its
  // peak angle is drawn at about 0.1 rad (a block's, which is seen, at x1).
  double peak_theta = 1e-12;
  for (const Response& r : main_rec.rows) peak_theta = std::max(peak_theta, std::abs(r[Quantity::theta]));
  const double kr = a.rotation > 0                                   ? a.rotation
                    : scene.structure.rigid || peak_theta < 1e-9      ? 1.0
                                                                     : std::max(1.0, nice(0.1 / peak_theta));
  // A factor the user gives draws the peak within the picture: the top's
  // displacement at most the height, the rocking angle at most pi/2 (on its side).
  if (a.exaggeration > 0 && !(a.exaggeration * top <= H))
    throw InputError(fmt::format("--exaggerate {:g}: draws the peak top displacement {:.3g} m as {:.3g} m; at most "
                                 "{:.3g} (the height, {:g} m)", a.exaggeration, top, a.exaggeration * top, H / top, H));
  double both_theta = peak_theta;  // the twin is drawn with the same factor
  for (const Response& r : twin_rec.rows) both_theta = std::max(both_theta, std::abs(r[Quantity::theta]));
  if (a.rotation > 0 && !(a.rotation * both_theta <= std::numbers::pi / 2))
    throw InputError(fmt::format("--exaggerate-rotation {:g}: draws the peak rocking angle {:.3g} rad as {:.3g} rad; "
                                 "at most {:.3g} (the structure on its side at pi/2)", a.rotation, both_theta,
                                 a.rotation * both_theta, std::numbers::pi / 2 / both_theta));
  const fs::path dir = gif.has_parent_path() ? gif.parent_path() : fs::path(".");
  const std::string stem = gif.stem().string();
  make_output_dir(dir / (stem + ".data"));
  write_frames(dir / (stem + ".data") / "main.dat", scene.structure, main_rec, k, kr, m, frames, main_model.has_damper);
  write_frames(dir / (stem + ".data") / "twin.dat", twin.structure, twin_rec, k, kr, m, frames, twin_model.has_damper);
  {
    std::ofstream tr(dir / (stem + ".data") / "traces.dat");
    // Named by the schema (rocking.quantities): the twin's moment as twin_base_moment; a_g in g.
    tr << "# t [s], a_g [g], M/M_ref main, M/M_ref twin, theta/alpha_cg main\n"
       << fmt::format("{} {} {} twin_{} {}\n", info(Quantity::t).name, info(Quantity::a_g).name,
                      info(Quantity::base_moment).name, info(Quantity::base_moment).name,
                      info(Quantity::theta_over_alpha).name);
    for (std::size_t i = 0; i < rows; ++i)
      tr << fmt::format("{:.6g} {:.6g} {:.6g} {:.6g} {:.6g}\n", main_rec.rows[i].t,
                        motion.acceleration(main_rec.rows[i].t) / gravity, main_rec.rows[i][Quantity::base_moment],
                        twin_rec.rows[i][Quantity::base_moment], main_rec.rows[i][Quantity::theta_over_alpha]);
  }
  const std::string twin_label = compare == "no-damper" ? "no damper" : variant_label(compare);
  // Alone: the structure spans the width, and the right trace is its rocking
  // angle (a block has no section forces); else the two side by side and the
  // base moments of both.
  // Every column by its header name (write_frames' x y part, the schema's
  // names in traces.dat).
  const std::string structure = fmt::format("({}):({} == 0 ? {} : NaN)", plot::column("x"), plot::column("part"),
                                            plot::column("y")),
                    damper = fmt::format("({}):({} == 1 ? {} : NaN)", plot::column("x"), plot::column("part"),
                                         plot::column("y"));
  auto trace = [](Quantity q, const std::string& prefix = "") {
    return fmt::format("({}):({})", plot::column(info(Quantity::t).name),
                       plot::column(prefix + std::string(info(q).name)));
  };
  const std::string panels =
      alone ? fmt::format(
                  "  set origin 0.25,0.38\n  set size 0.5,0.57\n  set title {} noenhanced\n"
                  "  plot d.\"main.dat\" index i using {structure} with linespoints lw 3 pt 7 ps 0.8 lc rgb \"#1f4e9c\", "
                  "d.\"main.dat\" index i using {damper} with lines lw 4 lc rgb \"#d35400\", "
                  "0 with lines lc rgb \"#555555\" lw 2\n",
                  plot::quote(scene.name), fmt::arg("structure", structure), fmt::arg("damper", damper))
            : fmt::format(
                  "  set origin 0,0.38\n  set size 0.5,0.57\n  set title {} noenhanced\n"
                  "  plot d.\"main.dat\" index i using {structure} with linespoints lw 3 pt 7 ps 0.8 lc rgb \"#1f4e9c\", "
                  "d.\"main.dat\" index i using {damper} with lines lw 4 lc rgb \"#d35400\", "
                  "0 with lines lc rgb \"#555555\" lw 2\n"
                  "  set origin 0.5,0.38\n  set size 0.5,0.57\n  set title {} noenhanced\n"
                  "  plot d.\"twin.dat\" index i using {structure} with linespoints lw 3 pt 7 ps 0.8 lc rgb \"#27864a\", "
                  "d.\"twin.dat\" index i using {damper} with lines lw 4 lc rgb \"#d35400\", "
                  "0 with lines lc rgb \"#555555\" lw 2\n",
                  plot::quote(scene.name), plot::quote(twin_label), fmt::arg("structure", structure),
                  fmt::arg("damper", damper));
  const std::string right_trace =
      alone ? fmt::format("  set ylabel \"rocking angle {{/Symbol q}}/{{/Symbol a}}_{{cg}}\"\n"
                          "  plot d.\"traces.dat\" using {} with lines lc rgb \"#1f4e9c\" notitle\n",
                          trace(Quantity::theta_over_alpha))
            // the key above the panel, off the traces; the twin dashed (greyscale print)
            : fmt::format("  set ylabel \"base moment M/M_{{ref}}\"\n"
                          "  set key outside top center horizontal nobox samplen 2.5 width 1\n"
                          "  plot d.\"traces.dat\" using {} with lines lc rgb \"#1f4e9c\" title \"rocking\", "
                          "'' using {} with lines dashtype 2 lc rgb \"#27864a\" title {}\n",
                          trace(Quantity::base_moment), trace(Quantity::base_moment, "twin_"), plot::quote(twin_label));
  const double span = std::max(3 * B, 0.5 * H);
  std::string script = fmt::format(
      "# rocking: animation ({} frames, {:.3g} s of simulation per frame). Re-render: gnuplot {}.gp\n"
      "{}"
      "set datafile columnheaders\n"
      "d = {}\n"
      "unset key\n"
      "do for [i={}:{}] {{\n"
      "  t = {} * i\n"
      "{}"
      "  set multiplot title {} . sprintf(\"%5.2f s\", t) . {} noenhanced\n"
      "  set size ratio -1\n  set xrange [{}:{}]\n  set yrange [-0.05*{}:1.1*{}]\n  unset xtics\n  set ytics\n  set ylabel \"height [m]\"\n"
      "{}"
      "  set size noratio\n  set autoscale xy\n  set xrange [{:.6g}:{:.6g}]\n  set xtics\n  set xlabel \"time t [s]\"\n  unset title\n"
      "  set arrow 1 from t, graph 0 to t, graph 1 nohead lc rgb \"#c0392b\" lw 2\n"
      "  set origin 0,0\n  set size 0.5,0.38\n  set ylabel \"a_g [g]\"\n"
      "  plot d.\"traces.dat\" using {} with lines lc rgb \"#555555\"\n"
      "  set origin 0.5,0\n  set size 0.5,0.38\n"
      "{}"
      "  unset key\n  unset arrow 1\n  unset xlabel\n"
      "  unset multiplot\n"
      "}}\n",
      last_frame - first_frame + 1, frame_dt, plot::comment(stem),
      video ? fmt::format("set terminal pngcairo size {},{} font \"DejaVu Sans,11\"\n", width, height)
            : fmt::format("set terminal gif animate delay {} size {},{} optimize font \"DejaVu Sans,11\"\n"
                          "set output {}\n", std::max(2, 100 / a.fps), width, height, plot::quote(stem + ".gif")),
      plot::quote(stem + ".data/"), first_frame, last_frame, frame_dt,
      video ? fmt::format("  set output {} . sprintf(\"%05d.png\", i)\n", plot::quote(stem + ".frames/")) : std::string(),
      plot::quote(fmt::format("{} - {}{}, {}   t = ", scene.name, describe_motion(motion.name()),
                              motion.vertical() ? " with vertical " + motion.vertical()->info().component : std::string(),
                              motion_scale(scene, a.motion).describe())),
      plot::quote(fmt::format("\n(drawn with rotation x{:g}, elastic deformation x{:g})", kr, k)), -span, span, H, H,
      panels, shown_from, shown_to, trace(Quantity::a_g), right_trace);
  plot::Figure fig;
  fig.dir = dir;
  fig.name = stem;
  fig.formats = video ? std::vector<std::string>{} : std::vector<std::string>{"gif"};  // video: PNG frames first
  if (video) make_output_dir(dir / (stem + ".frames"));
  plot::render_script(fig, script);
  if (video) {
    const fs::path log = dir / (stem + ".ffmpeg.log");
    std::vector<std::string> args{ffmpeg, "-y", "-loglevel", "error", "-framerate", std::to_string(a.fps), "-i",
                                  fs::absolute(dir / (stem + ".frames") / "%05d.png").string()};
    for (const char* c : ext == ".mp4" ? std::vector<const char*>{"-c:v", "libx264", "-pix_fmt", "yuv420p"}
                                       : std::vector<const char*>{"-c:v", "libvpx-vp9", "-b:v", "0", "-crf", "40"})
      args.emplace_back(c);
    args.push_back(fs::absolute(gif).string());
    if (plot::run_program(fs::current_path(), args, fs::absolute(log)) != 0 || !fs::is_regular_file(gif))
      throw RunError(fmt::format("ffmpeg failed on the frames of {} (see {})", gif.string(), log.string()));
    fs::remove_all(dir / (stem + ".frames"));
    fs::remove(log);
  }
  fmt::print("wrote {} ({} frames at {} fps, {:.2f} s of simulation per frame, rotation x{:g}, deformation x{:g})\n",
             gif.string(), last_frame - first_frame + 1, a.fps, frame_dt, kr, k);
  return 0;
}

}  // namespace

Command add_animate_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "animate",
      "Animated GIF of the structure drawn to scale (elastic deformation exaggerated\n"
      "by a stated factor) rocking about its pivots, the lifted edge and the stretched\n"
      "damper visible, beside its twin (--compare fixed-base or without:NAME) under the\n"
      "same motion, with a moving cursor on the ground-motion and base-moment traces.\n"
      "The frames' data and the gnuplot script are kept beside the GIF.");
  auto a = std::make_shared<AnimateArgs>();
  add_scene_options(*cmd, a->scene);
  add_motion_options(*cmd, a->motion);
  add_solver_options(*cmd, a->solver);
  cmd->add_option("--compare", a->compare,
                  "The twin: fixed-base (default), without:NAME (less the device the scene\n"
                  "names NAME, its [damper] included), no-damper, or none (the default for a\n"
                  "rigid block, drawn alone)")
      ->type_name("VARIANT");
  cmd->add_option("--out", a->out, "The animation: .gif (default out/animation.gif), or .mp4 / .webm when ffmpeg is installed")
      ->type_name("FILE");
  cmd->add_option("--speed", a->speed, "Simulated seconds per second of animation (default 1)")->type_name("X");
  cmd->add_option("--frames", a->max_frames, "At most this many frames (default 240)")->type_name("N");
  cmd->add_option("--fps", a->fps, "Frames per second (default 20)")->type_name("N");
  add_window_option(*cmd, a->window);
  cmd->add_option("--exaggerate", a->exaggeration, "Elastic deformation factor (default: top drawn at ~8 % of H)")
      ->type_name("K");
  cmd->add_option("--exaggerate-rotation", a->rotation,
                  "Rocking angle drawn x this, printed on every frame (default: the peak\n"
                  "drawn at about 0.1 rad, x1 for a rigid block)")
      ->type_name("K");
  cmd->add_option("--size", a->size, "GIF size in pixels (default 1000x700)")->type_name("WxH");
  cmd->footer("Example: rocking animate --record ../shared/data/records/elcentro_1940_ns.at2 --scale 3 --out plots/elcentro.gif");
  return [a]() { return animate(*a); };
}

}  // namespace rocking::app
