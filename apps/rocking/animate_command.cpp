// `rocking animate`: an animated GIF (gnuplot's gif animate terminal) of the
// structure drawn to scale, rocking about its pivots with its lifted edge and
// stretched damper, beside its twin (fixed base, or without a device) under the same
// record, with a moving cursor on the ground-motion and base-moment traces.
// A structure on rocking columns is drawn on its columns and cap beam, one
// with joints segment by segment with its tendons (rocking.drawing's
// columns_outline and chain_outline).
#include "commands.hpp"
#include "run_output.hpp"
#include "stop_signals.hpp"
#include "log.hpp"
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <numbers>
#include <span>
#include <tuple>
#include <utility>
#include <vector>
import rocking.drawing;
import rocking.errors;
import rocking.study;
import rocking.plot;

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

// Keeps the frames: the response, the elastic displacements and, for a
// structure with joints, every joint's rocking angle at each.
struct FrameRecorder : Observer {
  double interval;
  std::vector<Response> rows;
  std::vector<Eigen::VectorXd> u;
  std::vector<std::vector<double>> joint_thetas;  // per row: joint 0 (the base), 1, ... (empty without joints)
  Eigen::VectorXd next_u;  // the displacements of the row about to be recorded
  std::vector<double> next_joints;  // its joints' angles
  explicit FrameRecorder(double dt) : interval(dt) {}
  void record(const Response& r) override {
    // Keep the grid rows only (event rows fall between them).
    const double k = r.t / interval;
    if (std::abs(k - std::round(k)) < 1e-6 && (rows.empty() || r.t > rows.back().t)) {
      rows.push_back(r);
      u.push_back(next_u);
      joint_thetas.push_back(next_joints);
    }
  }
  void nodal(Eigen::Ref<const Eigen::VectorXd> v, Eigen::Ref<const Eigen::VectorXd>) override { next_u = v; }
  void joints(std::span<const JointSample> samples) override {
    next_joints.clear();
    for (const JointSample& j : samples) next_joints.push_back(j.theta);
  }
};

// The rocking angles a frame of the run draws, before the exaggeration: the
// body's theta; the columns' theta on rocking columns; every joint's theta
// (the base's first) for a structure with joints.
std::vector<double> rocking_angles(const ContactModel& model, const FrameRecorder& rec, std::size_t i) {
  if (model.jointed) return rec.joint_thetas[i];
  return {rec.rows[i][model.on_columns ? Quantity::columns_theta : Quantity::theta]};
}

double peak_angle(const ContactModel& model, const FrameRecorder& rec) {
  double peak = 0;
  for (std::size_t i = 0; i < rec.rows.size(); ++i)
    for (double th : rocking_angles(model, rec, i)) peak = std::max(peak, std::abs(th));
  return peak;
}

// How tall and how wide (half) the structure stands at rest, columns and
// segments included [m].
std::pair<double, double> picture_extent(const ContactModel& model, const Structure& s) {
  if (model.on_columns) {
    const Columns& c = model.on_columns->columns;
    const double reach = (c.axes.size() > 0 ? c.axes.cwiseAbs().maxCoeff() : 0.0) + c.group.half_width;
    return {2 * c.group.half_height + s.heights.maxCoeff(), reach};
  }
  if (model.jointed) {
    const ChainData& d = model.jointed->chain.data;
    double B = 0;
    for (const ChainSegment& g : d.segments) B = std::max(B, g.half_width);
    return {segment_top(d, static_cast<int>(d.segments.size()) - 1), B};
  }
  return {s.heights.maxCoeff(), s.half_width};
}

double nice(double x) {  // 1, 2 or 5 x 10^k, not above x
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * p <= x) return m * p;
  return p;
}

// What a row of the frames' data is (its `part` column), for the script:
// the structure's axis and nodes, a device drawn, a device not drawn (no edge
// lifted), an outline (a column, a segment), the cap beam.
enum Part { axis_part = 0, device_part = 1, hidden_part = 2, outline_part = 3, beam_part = 4 };

void write_point(std::ostream& out, const Point& p, Part part) {
  out << fmt::format("{:.9g} {:.9g} {}\n", p.first, p.second, static_cast<int>(part));
}
void write_piece(std::ostream& out, const std::vector<Point>& points, Part part) {
  for (const Point& p : points) write_point(out, p, part);
  out << '\n';
}

// Every m-th recorded row is a frame: one block each (gnuplot's index), its
// time in a comment above its header; pieces within it apart by a blank line.
void write_frames(const fs::path& file, const ContactModel& model, const Structure& s, const FrameRecorder& rec,
                  double k, double kr, int m, std::size_t frames) {
  std::ofstream out(file);
  out << "# one block per frame (index i), each under its header; part 0: the structure's axis and nodes, 1: a "
         "device, 2: a device not drawn, 3: an outline (a column, a segment), 4: the cap beam\n";
  for (std::size_t f = 0; f < frames; ++f) {
    const std::size_t i = f * static_cast<std::size_t>(m);
    const Response& r = rec.rows[i];
    out << fmt::format("# frame {}, t = {:.9g} s\nx y part\n", f, r.t);
    const Eigen::VectorXd u = i < rec.u.size() ? rec.u[i] : Eigen::VectorXd();
    std::vector<double> angles = rocking_angles(model, rec, i);
    for (double& th : angles) th *= kr;
    if (model.on_columns) {
      const ColumnsOutline o = columns_outline(model.on_columns->columns, angles[0], u, k);
      for (const auto& c : o.columns) write_piece(out, {c[0], c[1], c[2], c[3], c[0]}, outline_part);
      write_piece(out, {o.beam_left, o.beam_right}, beam_part);
      write_piece(out, o.axis, axis_part);
    } else if (model.jointed) {
      const ChainOutline o = chain_outline(model.jointed->chain.data, angles);
      for (const SegmentOutline& g : o.segments) {
        write_piece(out, {g.base_left, g.base_right, g.top_right, g.top_left, g.base_left}, outline_part);
        write_piece(out, g.axis, axis_part);
      }
      for (const auto& [from, to] : o.tendons) write_piece(out, {from, to}, device_part);
    } else {
      const Outline o = outline(s, r.phase, angles[0], u, k);
      const Part damper = model.has_damper ? device_part : hidden_part;
      write_piece(out, o.axis, axis_part);
      write_piece(out, {o.left_corner, o.right_corner}, axis_part);
      write_piece(out, {o.damper_anchor, o.damper_end}, damper);
    }
    out << '\n';
  }
}

// What the output asks for: a GIF, or a video through ffmpeg (its path).
struct Output {
  bool video = false;
  std::string ffmpeg;
  int width = 0, height = 0;
};

// The options that need no run, refused in one line each.
Output check_options(const AnimateArgs& a) {
  const std::string ext = fs::path(a.out).extension().string();
  if (ext != ".gif" && ext != ".mp4" && ext != ".webm")
    throw InputError(fmt::format("--out {}: write .gif, or .mp4 / .webm (with ffmpeg)", a.out));
  Output o;
  o.video = ext != ".gif";
  o.ffmpeg = o.video ? plot::find_program("ffmpeg") : "";
  if (o.video && o.ffmpeg.empty())
    throw InputError(fmt::format("--out {}: MP4 and WebM need ffmpeg, which is not installed (apt install ffmpeg); "
                                 "write a .gif instead", a.out));
  if (!(a.speed > 0)) throw InputError(fmt::format("--speed {}: must be positive", a.speed));
  if (a.max_frames < 2 || a.max_frames > 2000) throw InputError(fmt::format("--frames {}: must be 2 to 2000", a.max_frames));
  std::tie(o.width, o.height) = plot::parse_size(a.size, 300, 200, 4000);
  for (const auto& [value, flag] : {std::pair{a.exaggeration, "--exaggerate"}, std::pair{a.rotation, "--exaggerate-rotation"}})
    if (!std::isfinite(value) || value < 0)
      throw InputError(fmt::format("{} {}: must be a positive number (0: automatic)", flag, value));
  if (a.fps < 1 || a.fps > 100) throw InputError(fmt::format("--fps {}: must be 1 to 100", a.fps));
  return o;
}

// The twin drawn beside the scene: --compare, or by default the fixed base
// (none for a rigid block, a structure with joints, whose chain rocks at its
// base, or one on rocking columns, whose contact.rocking = false holds the
// columns with the beam still free on them: rocking.study's default_variants).
std::string twin_of(const AnimateArgs& a, const Scene& scene) {
  const bool no_fixed_twin = scene.structure.rigid || scene.jointed() || scene.columns.has_value();
  const std::string compare = !a.compare.empty() ? a.compare : no_fixed_twin ? "none" : "fixed-base";
  if (compare != "fixed-base" && compare != "no-damper" && compare != "none" && !compare.starts_with("without:"))
    throw InputError(fmt::format("--compare {}: choose fixed-base, without:NAME (a device the scene names), no-damper "
                                 "or none", compare));
  return compare;
}

// The frames in time: the span shown, one frame every frame_dt, every m-th
// recorded row (the traces are sampled more finely than the frames).
struct Timing {
  double shown_from = 0, shown_to = 0, frame_dt = 0;
  int m = 1;
};

Timing frame_timing(const AnimateArgs& a, double duration, const GroundMotion& motion) {
  Timing t;
  // The span animated: --window (the run computes from t = 0 all the same).
  const auto window = time_window(a.window, {&motion});
  t.shown_from = window ? std::min((*window)[0], duration) : 0.0;
  t.shown_to = window ? std::min((*window)[1], duration) : duration;
  if (!(t.shown_to > t.shown_from))
    throw InputError(fmt::format("--window {}: the run ends at {:g} s", a.window, duration));
  const double shown = t.shown_to - t.shown_from;
  // At least two frames over the span shown: one per frame interval speed / fps.
  if (!(a.speed <= shown * a.fps))
    throw InputError(fmt::format("--speed {:g}: at most {:.4g} (two frames over the {:g} s shown at {} fps)", a.speed,
                                 shown * a.fps, shown, a.fps));
  // Frame times: real time / speed at fps, at most max_frames over the span shown.
  t.frame_dt = a.speed / a.fps;
  if (shown / t.frame_dt + 1 > a.max_frames) t.frame_dt = shown / (a.max_frames - 1);
  t.m = std::max(1, static_cast<int>(std::ceil(t.frame_dt / 0.01 - 1e-9)));
  return t;
}

// The two runs as `rocking simulate` makes them (rocking.run), under the
// motion read once, each recording its frames; the frames read no energy.
struct Runs {
  PreparedRun main, twin;
  FrameRecorder main_rec{0.01}, twin_rec{0.01};
  Timing timing;
};

std::unique_ptr<Runs> run_both(const AnimateArgs& a, const Scene& scene, const Scene& twin, const GroundMotion& motion) {
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
  // The run prepared once: its duration, checked, sets the frames, which set
  // how often it records.
  auto r = std::make_unique<Runs>(Runs{.main = prepared(scene, 0.01), .twin = {}, .timing = {}});
  const RunOptions& ro = r->main.options;
  r->timing = frame_timing(a, ro.duration > 0 ? ro.duration : motion.duration(), motion);
  const double every = r->timing.frame_dt / r->timing.m;
  r->main.options.output_interval = every;
  r->twin = prepared(twin, every);
  r->main_rec = FrameRecorder(r->main.options.output_interval);
  r->twin_rec = FrameRecorder(r->twin.options.output_interval);
  const RunResult r1 = simulate(r->main.model, r->main.motion, r->main.options, &r->main_rec);
  const RunResult r2 = simulate(r->twin.model, r->twin.motion, r->twin.options, &r->twin_rec);
  for (const RunResult* result : {&r1, &r2})
    if (result->outcome == Outcome::failed) throw RunError(result->failure);
  return r;
}

// How much the drawing exaggerates: the elastic deformation x k, the rocking
// angles x kr; a factor the user gives must keep the peak within the picture.
struct Exaggeration {
  double k = 1, kr = 1;
};

Exaggeration exaggeration(const AnimateArgs& a, const Scene& scene, const Runs& r) {
  const double H = scene.structure.heights.maxCoeff();
  double top = 1e-12;
  for (const Response& row : r.main_rec.rows) top = std::max(top, std::abs(row[Quantity::u_top]));
  for (const Response& row : r.twin_rec.rows) top = std::max(top, std::abs(row[Quantity::u_top]));
  Exaggeration e;
  e.k = a.exaggeration > 0 ? a.exaggeration : scene.structure.rigid ? 1.0 : std::max(1.0, nice(0.08 * H / top));
  // The rocking of a tall structure is invisible at true scale: by default its
  // peak angle is drawn at about 0.1 rad (a block's, which is seen, at x1).
  // The angle is the body's, the columns' on rocking columns, each joint's
  // for a structure with joints.
  const double peak_theta = std::max(1e-12, peak_angle(r.main.model, r.main_rec));
  e.kr = a.rotation > 0                                   ? a.rotation
         : scene.structure.rigid || peak_theta < 1e-9      ? 1.0
                                                          : std::max(1.0, nice(0.1 / peak_theta));
  // A factor the user gives draws the peak within the picture: the top's
  // displacement at most the height, the rocking angle at most pi/2 (on its side).
  if (a.exaggeration > 0 && !(a.exaggeration * top <= H))
    throw InputError(fmt::format("--exaggerate {:g}: draws the peak top displacement {:.3g} m as {:.3g} m; at most "
                                 "{:.3g} (the height, {:g} m)", a.exaggeration, top, a.exaggeration * top, H / top, H));
  const double both_theta = std::max(peak_theta, peak_angle(r.twin.model, r.twin_rec));  // the twin is drawn with the same factor
  if (a.rotation > 0 && !(a.rotation * both_theta <= std::numbers::pi / 2))
    throw InputError(fmt::format("--exaggerate-rotation {:g}: draws the peak rocking angle {:.3g} rad as {:.3g} rad; "
                                 "at most {:.3g} (the structure on its side at pi/2)", a.rotation, both_theta,
                                 a.rotation * both_theta, std::numbers::pi / 2 / both_theta));
  return e;
}

// The main run's rocking angles drawn (before the factor kr) and each over
// its slenderness, named by the schema: theta, or columns.theta, or theta and
// jointK.theta; the right trace of a structure drawn alone.
struct AngleNames {
  std::vector<std::string> angles, ratios;
};

AngleNames angle_names(const ContactModel& model) {
  AngleNames n;
  if (model.on_columns) {
    n.angles = {std::string(info(Quantity::columns_theta).name)};
    n.ratios = {std::string(info(Quantity::columns_theta_over_alpha).name)};
    return n;
  }
  n.angles = {std::string(info(Quantity::theta).name)};
  n.ratios = {std::string(info(Quantity::theta_over_alpha).name)};
  if (model.jointed)
    for (int j = 1; j < model.jointed->chain.joints; ++j) {
      n.angles.push_back(JointQuantityName{j, JointQuantity::theta}.name());
      n.ratios.push_back(JointQuantityName{j, JointQuantity::theta_over_alpha}.name());
    }
  return n;
}

// traces.dat: the ground motion, both base moments and the main run's
// rocking angles, named by the schema (rocking.quantities): the twin's moment
// as twin_base_moment; a_g in g.
void write_traces(const fs::path& file, const Runs& r, const GroundMotion& motion, const AngleNames& names) {
  const ContactModel& model = r.main.model;
  const std::size_t rows = std::min(r.main_rec.rows.size(), r.twin_rec.rows.size());
  std::ofstream tr(file);
  tr << "# t [s], a_g [g], M/M_ref main, M/M_ref twin, then the main run's rocking angles [rad] and each over "
        "its slenderness\n"
     << fmt::format("{} {} {} twin_{} {} {}\n", info(Quantity::t).name, info(Quantity::a_g).name,
                    info(Quantity::base_moment).name, info(Quantity::base_moment).name, fmt::join(names.angles, " "),
                    fmt::join(names.ratios, " "));
  for (std::size_t i = 0; i < rows; ++i) {
    const Response& row = r.main_rec.rows[i];
    const std::vector<double> angles = rocking_angles(model, r.main_rec, i);
    tr << fmt::format("{:.6g} {:.6g} {:.6g} {:.6g}", row.t, motion.acceleration(row.t) / gravity,
                      row[Quantity::base_moment], r.twin_rec.rows[i][Quantity::base_moment]);
    for (double th : angles) tr << fmt::format(" {:.9g}", th);
    if (model.jointed)  // over the slenderness of everything above each joint (jointK.theta_over_alpha's)
      for (std::size_t j = 0; j < angles.size(); ++j) tr << fmt::format(" {:.6g}", angles[j] / model.jointed->overturn_angle[j]);
    else  // the schema's ratio (a single body's over alpha_cg, the columns' over their alpha)
      tr << fmt::format(" {:.6g}", row[model.on_columns ? Quantity::columns_theta_over_alpha : Quantity::theta_over_alpha]);
    tr << '\n';
  }
}

// The gnuplot `using` of a frame's part and of a trace, every column by its
// header name (write_frames' x y part, the schema's names in traces.dat).
std::string part_using(Part p) {
  return fmt::format("({}):({} == {} ? {} : NaN)", plot::column("x"), plot::column("part"), static_cast<int>(p),
                     plot::column("y"));
}
std::string trace_using(Quantity q, const std::string& prefix = "") {
  return fmt::format("({}):({})", plot::column(info(Quantity::t).name), plot::column(prefix + std::string(info(q).name)));
}

// One run's drawing: the columns or segments outlined and the cap beam where
// the model has them, the axis with its nodes, the devices, the ground.
std::string drawing(const char* file, const ContactModel& model, const char* color) {
  std::string out = fmt::format("  plot d.\"{}\" index i using {} with linespoints lw 3 pt 7 ps 0.8 lc rgb \"{}\", ",
                                file, part_using(axis_part), color);
  // A single body's damper (part 2 while no edge is lifted) and a chain's tendons; a structure on columns draws none.
  if (model.jointed ? !model.jointed->chain.data.tendons.empty() : !model.on_columns)
    out += fmt::format("d.\"{}\" index i using {} with lines lw 4 lc rgb \"#d35400\", ", file, part_using(device_part));
  if (model.on_columns || model.jointed)
    out += fmt::format("d.\"{}\" index i using {} with lines lw 2 lc rgb \"{}\", ", file, part_using(outline_part), color);
  if (model.on_columns)
    out += fmt::format("d.\"{}\" index i using {} with lines lw 6 lc rgb \"#555555\", ", file, part_using(beam_part));
  return out + "0 with lines lc rgb \"#555555\" lw 2\n";
}

// Alone, the rocking angles over their slenderness: the body's, the
// columns', or every joint's (one curve each, the key above the panel).
// Greek letters as UTF-8: the GIF terminal has no Symbol font, and drops a
// label that asks for one.
std::string angle_trace(const ContactModel& model, const AngleNames& names) {
  if (model.on_columns)
    return fmt::format("  set ylabel \"columns θ_c/α_c\"\n"
                       "  plot d.\"traces.dat\" using {} with lines lc rgb \"#1f4e9c\" notitle\n",
                       trace_using(Quantity::columns_theta_over_alpha));
  if (model.jointed) {
    std::vector<std::string> curves;
    for (std::size_t j = 0; j < names.ratios.size(); ++j)
      curves.push_back(fmt::format("{}using ({}):({}) with lines lw 2 title \"{}\"", j == 0 ? "d.\"traces.dat\" " : "'' ",
                                   plot::column(info(Quantity::t).name), plot::column(names.ratios[j]),
                                   j == 0 ? std::string("base") : fmt::format("joint {}", j)));
    return fmt::format("  set ylabel \"joints θ_j/α_j\"\n"
                       "  set key outside top center horizontal nobox samplen 2.5 width 1\n"
                       "  plot {}\n", fmt::join(curves, ", "));
  }
  return fmt::format("  set ylabel \"rocking angle θ/α_{{cg}}\"\n"
                     "  plot d.\"traces.dat\" using {} with lines lc rgb \"#1f4e9c\" notitle\n",
                     trace_using(Quantity::theta_over_alpha));
}

// What the script draws beyond the runs' data: which frames, how they are
// exaggerated, the twin's name and the title's words.
struct ScriptParts {
  std::string stem, title, twin_label;
  std::size_t first_frame = 0, last_frame = 0;
  Timing timing;
  Exaggeration exaggeration;
  bool alone = false;
};

// The gnuplot script: one multiplot per frame (the structure, or the two side
// by side; the ground motion under it; beside that the base moments, or alone
// the rocking angles), written to a GIF or to PNG frames for ffmpeg.
std::string animation_script(const AnimateArgs& a, const Output& o, const Scene& scene, const Runs& r,
                             const AngleNames& names, const ScriptParts& s) {
  const ContactModel &main_model = r.main.model, &twin_model = r.twin.model;
  // Alone: the structure spans the width, and the right trace is its rocking
  // angle (a block has no section forces); else the two side by side and the
  // base moments of both.
  const std::string panels =
      s.alone ? fmt::format("  set origin 0.25,0.38\n  set size 0.5,0.57\n  set title {} noenhanced\n{}",
                            plot::quote(scene.name), drawing("main.dat", main_model, "#1f4e9c"))
              : fmt::format("  set origin 0,0.38\n  set size 0.5,0.57\n  set title {} noenhanced\n{}"
                            "  set origin 0.5,0.38\n  set size 0.5,0.57\n  set title {} noenhanced\n{}",
                            plot::quote(scene.name), drawing("main.dat", main_model, "#1f4e9c"),
                            plot::quote(s.twin_label), drawing("twin.dat", twin_model, "#27864a"));
  const std::string right_trace =
      s.alone ? angle_trace(main_model, names)
              // the key above the panel, off the traces; the twin dashed (greyscale print)
              : fmt::format("  set ylabel \"base moment M/M_{{ref}}\"\n"
                            "  set key outside top center horizontal nobox samplen 2.5 width 1\n"
                            "  plot d.\"traces.dat\" using {} with lines lc rgb \"#1f4e9c\" title \"rocking\", "
                            "'' using {} with lines dashtype 2 lc rgb \"#27864a\" title {}\n",
                            trace_using(Quantity::base_moment), trace_using(Quantity::base_moment, "twin_"),
                            plot::quote(s.twin_label));
  // The picture: the structure standing (columns and segments included) and
  // room beside it to rock; columns span their spacing, so less is added.
  const auto [tall, reach] = picture_extent(main_model, scene.structure);
  const double span = std::max((main_model.on_columns ? 1.5 : 3.0) * reach, 0.5 * tall);
  const double frame_dt = s.timing.frame_dt;
  return fmt::format(
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
      s.last_frame - s.first_frame + 1, frame_dt, plot::comment(s.stem),
      o.video ? fmt::format("set terminal pngcairo size {},{} font \"DejaVu Sans,11\"\n", o.width, o.height)
              : fmt::format("set terminal gif animate delay {} size {},{} optimize font \"DejaVu Sans,11\"\n"
                            "set output {}\n", std::max(2, 100 / a.fps), o.width, o.height, plot::quote(s.stem + ".gif")),
      plot::quote(s.stem + ".data/"), s.first_frame, s.last_frame, frame_dt,
      o.video ? fmt::format("  set output {} . sprintf(\"%05d.png\", i)\n", plot::quote(s.stem + ".frames/")) : std::string(),
      plot::quote(s.title),
      plot::quote(fmt::format("\n(drawn with rotation x{:g}, elastic deformation x{:g})", s.exaggeration.kr,
                              s.exaggeration.k)),
      -span, span, tall, tall, panels, s.timing.shown_from, s.timing.shown_to, trace_using(Quantity::a_g), right_trace);
}

// The PNG frames in DIR/STEM.frames made into the video by ffmpeg, then removed.
void encode_video(const AnimateArgs& a, const Output& o, const fs::path& dir, const std::string& stem) {
  const fs::path out(a.out);
  const fs::path log = dir / (stem + ".ffmpeg.log");
  std::vector<std::string> args{o.ffmpeg, "-y", "-loglevel", "error", "-framerate", std::to_string(a.fps), "-i",
                                fs::absolute(dir / (stem + ".frames") / "%05d.png").string()};
  for (const char* c : out.extension() == ".mp4" ? std::vector<const char*>{"-c:v", "libx264", "-pix_fmt", "yuv420p"}
                                                 : std::vector<const char*>{"-c:v", "libvpx-vp9", "-b:v", "0", "-crf", "40"})
    args.emplace_back(c);
  args.push_back(fs::absolute(out).string());
  if (plot::run_program(fs::current_path(), args, fs::absolute(log)) != 0 || !fs::is_regular_file(out))
    throw RunError(fmt::format("ffmpeg failed on the frames of {} (see {})", out.string(), log.string()));
  fs::remove_all(dir / (stem + ".frames"));
  fs::remove(log);
}

int animate(const AnimateArgs& a) {
  const Output o = check_options(a);
  const Scene scene = load_scene(a.scene);
  const GroundMotion motion = load_motion(scene, a.motion);
  const std::string compare = twin_of(a, scene);
  const bool alone = compare == "none";
  std::vector<std::string> twin_overrides = a.scene.overrides;
  if (!alone) {
    const Variant twin_variant = named_variant(compare);
    twin_overrides.insert(twin_overrides.end(), twin_variant.overrides.begin(), twin_variant.overrides.end());
  }
  const Scene twin = load_scene(SceneOptions{a.scene.path, twin_overrides});
  const std::unique_ptr<Runs> runs = run_both(a, scene, twin, motion);
  const Runs& r = *runs;
  const Timing& timing = r.timing;
  const auto m = static_cast<std::size_t>(timing.m);
  const std::size_t rows = std::min(r.main_rec.rows.size(), r.twin_rec.rows.size());
  const std::size_t frames = (rows + m - 1) / m;
  ScriptParts parts{.stem = fs::path(a.out).stem().string(), .title = {}, .twin_label = {}, .timing = timing, .exaggeration = {}, .alone = alone};
  parts.first_frame = static_cast<std::size_t>(std::ceil(timing.shown_from / timing.frame_dt - 1e-9));
  parts.last_frame =
      std::min(frames, static_cast<std::size_t>(std::floor(timing.shown_to / timing.frame_dt + 1e-9)) + 1) - 1;
  if (frames < 2 || parts.last_frame < parts.first_frame + 1)
    throw InputError("animation: the span shown is too short for two frames");
  parts.exaggeration = exaggeration(a, scene, r);
  const fs::path gif(a.out);
  const fs::path dir = gif.has_parent_path() ? gif.parent_path() : fs::path(".");
  const fs::path data = dir / (parts.stem + ".data");
  make_output_dir(data);
  const auto [k, kr] = parts.exaggeration;
  write_frames(data / "main.dat", r.main.model, scene.structure, r.main_rec, k, kr, timing.m, frames);
  write_frames(data / "twin.dat", r.twin.model, twin.structure, r.twin_rec, k, kr, timing.m, frames);
  const AngleNames names = angle_names(r.main.model);
  write_traces(data / "traces.dat", r, motion, names);
  // On rocking columns, contact.rocking = false holds the columns down; the beam still rests on them.
  parts.twin_label = compare == "no-damper"                      ? "no damper"
                     : compare == "fixed-base" && scene.columns ? "columns held down"
                                                                : variant_label(compare);
  parts.title = fmt::format("{} - {}{}, {}   t = ", scene.name, describe_motion(motion.name()),
                            motion.vertical() ? " with vertical " + motion.vertical()->info().component : std::string(),
                            motion_scale(scene, a.motion).describe());
  plot::Figure fig;
  fig.dir = dir;
  fig.name = parts.stem;
  fig.formats = o.video ? std::vector<std::string>{} : std::vector<std::string>{"gif"};  // video: PNG frames first
  if (o.video) make_output_dir(dir / (parts.stem + ".frames"));
  plot::render_script(fig, animation_script(a, o, scene, r, names, parts));
  if (o.video) encode_video(a, o, dir, parts.stem);
  fmt::print("wrote {} ({} frames at {} fps, {:.2f} s of simulation per frame, rotation x{:g}, deformation x{:g})\n",
             gif.string(), parts.last_frame - parts.first_frame + 1, a.fps, timing.frame_dt, kr, k);
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
      "A structure on [columns] is drawn on its rocking columns and cap beam; one with\n"
      "[[joint]]s segment by segment, each turning about its joint's corner.\n"
      "The frames' data and the gnuplot script are kept beside the GIF.");
  auto a = std::make_shared<AnimateArgs>();
  add_scene_options(*cmd, a->scene);
  add_motion_options(*cmd, a->motion);
  add_solver_options(*cmd, a->solver);
  cmd->add_option("--compare", a->compare,
                  "The twin: fixed-base (default), without:NAME (less the device the scene\n"
                  "names NAME, its [damper] included), no-damper, or none (the default for a\n"
                  "rigid block, a structure with joints or one on rocking columns, drawn alone)")
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
