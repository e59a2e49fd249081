module;
#include <rocking/eigen.hpp>
#include <cmath>
#include <algorithm>
#include <functional>
#include <iterator>
#include <limits>
#include <tuple>
#include <utility>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>
#include <thread>
#include <fmt/format.h>
module rocking.study;
import rocking.errors;
import rocking.records;

namespace rocking {

namespace {
// The value as its decimal reads to 12 digits (1.3, not 1.2999999999999998).
double decimal(double v) { return std::stod(fmt::format("{:.12g}", v)); }
}  // namespace

Variant named_variant(const std::string& name) {
  if (name == "scene") return {name, {}};
  if (name == "damper") return {name, {"damper.enabled=true"}};
  if (name == "no-damper") return {name, {"damper.enabled=false"}};
  if (name == "fixed-base") return {name, {"contact.rocking=false"}};
  if (name == "no-devices") return {name, {"damper.enabled=false", "device=[]"}};
  if (name.starts_with("without:") && name.size() > 8) return {name, {"device-=" + name.substr(8)}};
  throw InputError(fmt::format("unknown variant '{}' (choose from damper, no-damper, fixed-base, scene, no-devices, "
                               "without:NAME)", name));
}

std::vector<Variant> default_variants(const Scene& scene) {
  std::vector<Variant> out{named_variant("scene")};
  for (const DeviceGroup& g : device_groups(scene))
    if (g.dissipates) out.push_back(named_variant("without:" + g.name));
  // On a fixed base a rigid structure has no motion unless it has joints above its base, which still rock
  // there (MODEL.md 15). A structure on rocking columns has no fixed-base variant: contact.rocking = false
  // there holds the columns still, with the beam still free on them (MODEL.md 16), which is not the
  // structure on a fixed base.
  if (scene.contact.rocking && !scene.columns && (!scene.structure.rigid || !scene.joints.empty()))
    out.push_back(named_variant("fixed-base"));
  return out;
}

namespace {

std::vector<StudyRecord> files(const std::vector<std::string>& paths) {
  std::vector<StudyRecord> out;
  for (const std::string& p : paths) out.push_back({p, nullptr});
  return out;
}

}  // namespace

Study::Study(const std::string& scene_path, const std::vector<std::string>& common_overrides,
             std::vector<std::string> records, RecordOptions record_options, std::vector<Variant> variants,
             RunOptions run_options, IntensityMeasure im)
    : Study(scene_path, common_overrides, files(records), record_options, std::move(variants), run_options, im) {}

Study::Study(const std::string& scene_path, const std::vector<std::string>& common_overrides,
             const std::vector<StudyRecord>& records, RecordOptions record_options, std::vector<Variant> variants,
             RunOptions run_options, IntensityMeasure im)
    : variants_(std::move(variants)), im_(im), options_(run_options) {
  for (const StudyRecord& rec : records) {
    const std::string& r = rec.name;
    records_.push_back(r);
    motions_.emplace_back(std::nullopt);
    record_errors_.emplace_back();
    record_im_.push_back(std::numeric_limits<double>::quiet_NaN());
    try {
      if (rec.motion) motions_.back().emplace(*rec.motion);
      else motions_.back().emplace(read_record(r, record_options));
      const double own = intensity(*motions_.back(), im_);
      if (!(own > 0) || !std::isfinite(own))
        throw InputError(fmt::format("{}: its {} is {:g}: it cannot be scaled to a level", r, im_.name(), own));
      record_im_.back() = own;
    } catch (const InputError& e) {
      motions_.back().reset();
      record_errors_.back() = e.what();
    }
  }
  for (const Variant& v : variants_) {
    std::vector<std::string> overrides = common_overrides;
    overrides.insert(overrides.end(), v.overrides.begin(), v.overrides.end());
    try {
      const Scene scene = scene_path.empty() ? load_default_scene(overrides) : load_scene(scene_path, overrides);
      models_.emplace_back(make_contact_model(scene, false));
      variant_errors_.emplace_back();
    } catch (const InputError& e) {
      models_.emplace_back(std::nullopt);
      variant_errors_.emplace_back(e.what());
    }
  }
}

Job Study::at_level(std::size_t record, std::size_t variant, double level) const {
  // For "sf" the record's IM is 1 and the scale is the level itself.
  const double own = record_im_[record];
  return {record, std::isfinite(own) ? level / own : level, variant, level};
}

std::vector<Job> Study::ladder(const std::vector<double>& levels) const {
  std::vector<Job> jobs;
  for (std::size_t r = 0; r < records_.size(); ++r)
    for (double level : levels)
      for (std::size_t v = 0; v < variants_.size(); ++v) jobs.push_back(at_level(r, v, level));
  return jobs;
}

JobResult Study::run(const Job& job) const {
  JobResult out;
  if (!record_errors_[job.record].empty()) out.error = record_errors_[job.record];
  else if (!variant_errors_[job.variant].empty()) out.error = variant_errors_[job.variant];
  if (!out.error.empty()) {
    out.run.outcome = Outcome::failed;
    return out;
  }
  try {
    out.run = simulate(*models_[job.variant], motions_[job.record]->scaled(job.scale), options_);
  } catch (const InputError& e) {  // a level beyond what check_level allows
    out.run.outcome = Outcome::failed;
    out.error = e.what();
    return out;
  }
  if (out.run.outcome == Outcome::failed) out.error = out.run.failure;
  // The momentum law left the outcome open: a row without a result, saying why.
  if (out.run.outcome == Outcome::undecided) out.error = "undecided: " + out.run.stated;
  return out;
}

WorkerThreads worker_threads(int requested, std::string_view option) {
  if (requested < 0) throw InputError(fmt::format("{} {}: must be at least 1 (0: every core)", option, requested));
  WorkerThreads w;
  w.cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int most = 4 * w.cores;
  w.capped = requested > most;
  w.threads = w.capped ? most : requested > 0 ? requested : w.cores;
  return w;
}

void Study::check_level(double level, std::string_view option) const {
  for (std::size_t r = 0; r < records_.size(); ++r) {
    if (!motions_[r]) continue;
    try {
      (void)motions_[r]->scaled(at_level(r, 0, level).scale);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{} {:g}: {}: {}", option, level, records_[r], e.what()));
    }
  }
}

bool Study::can_overturn(std::size_t variant) const {
  return !models_[variant] || models_[variant]->kind != ModelKind::fixed_base;
}

bool Study::reports(std::size_t variant, const QuantityName& q) const {
  if (!models_[variant]) return false;
  if (q.scalar) return presence(*models_[variant]).has(info(*q.scalar).needs);
  if (q.joint) return q.joint->joint <= joints(variant);
  return std::ranges::any_of(models_[variant]->devices, [&](const Device& d) { return d.name == q.device; });
}

int Study::joints(std::size_t variant) const {
  return models_[variant] && models_[variant]->jointed ? models_[variant]->jointed->chain.joints - 1 : 0;
}

std::vector<std::string> Study::device_names(std::size_t variant) const {
  std::vector<std::string> out;
  if (models_[variant])
    for (const Device& d : models_[variant]->devices) out.push_back(d.name);
  return out;
}

// More values than any study runs in a day (and a bound on the memory a typo reserves).
constexpr std::size_t max_list_values = 1000001;

std::vector<double> parse_number_list(const std::string& text) {
  auto fail = [&] {
    throw InputError(fmt::format("'{}': expected FIRST:LAST:STEP (e.g. 1:20:1) or a list (0.5,1,2)", text));
  };
  std::vector<double> out;
  auto number = [&](const std::string& s) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(s, &used);
    } catch (...) {
      fail();
    }
    if (used != s.size() || !std::isfinite(v)) fail();
    return v;
  };
  if (text.find(':') != std::string::npos) {
    std::vector<std::string> parts;
    std::stringstream ss(text);
    for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
    if (parts.size() != 3) fail();
    const double first = number(parts[0]), last = number(parts[1]), step = number(parts[2]);
    if (!(step > 0))
      throw InputError(fmt::format("'{}': STEP {:g} must be positive (FIRST:LAST:STEP counts up from FIRST)", text, step));
    if (last < first)
      throw InputError(fmt::format("'{}': LAST {:g} is below FIRST {:g} (FIRST:LAST:STEP counts up)", text, last, first));
    if ((last - first) / step > max_list_values - 1)
      throw InputError(fmt::format("'{}': {:.3g} values; a list holds at most {} (a larger STEP or a shorter span)",
                                   text, std::floor((last - first) / step) + 1, max_list_values));
    const auto n = static_cast<long>(std::floor((last - first) / step + 1e-9));
    // Each value as its decimal reads (0.15, not 0.15000000000000002).
    for (long i = 0; i <= n; ++i) out.push_back(decimal(first + static_cast<double>(i) * step));
  } else {
    if (text.ends_with(",")) fail();
    std::stringstream ss(text);
    for (std::string p; std::getline(ss, p, ',');) out.push_back(number(p));
    if (out.size() > max_list_values)
      throw InputError(fmt::format("'{}': {} values; a list holds at most {}", text, out.size(), max_list_values));
  }
  if (out.empty()) fail();
  return out;
}

void check_hunt_options(const HuntOptions& o) {
  for (const auto& [name, v] : {std::pair{"first level", o.first}, {"--hunt-step", o.step}, {"--hunt-max", o.max},
                                {"--precision", o.precision}, {"--fill-step", o.fill_step}, {"--hunt-growth", o.growth}})
    if (!(v > 0) || !std::isfinite(v)) throw InputError(fmt::format("{} {}: must be positive and finite", name, v));
  if (o.growth < 1) throw InputError(fmt::format("--hunt-growth {}: must be at least 1 (the step grows)", o.growth));
  if (o.max < o.first)
    throw InputError(fmt::format("--hunt-max {:g}: below the first level {:g}, the hunt would run nothing", o.max, o.first));
  // The fill is the most runs: one per fill step up to --hunt-max.
  const double runs = (o.max - o.first) / std::min(o.step, o.fill_step) + std::log2(o.max / o.precision) + 2;
  if (runs > 1e5)
    throw InputError(fmt::format("--hunt-step {:g}, --fill-step {:g}: up to {:.3g} runs per record and variant (at "
                                 "most 1e5); take larger steps",
                                 o.step, o.fill_step, runs));
  // Below 1e-9 of the largest level a bisection no longer parts distinct levels.
  if (o.precision < 1e-9 * o.max)
    throw InputError(fmt::format("--precision {:g}: at least 1e-9 x --hunt-max ({:g}): finer brackets are round-off",
                                 o.precision, 1e-9 * o.max));
}

HuntOptions hunt_options(double first, std::optional<double> step, double growth, std::optional<double> max,
                         std::optional<double> precision, std::optional<double> fill_step) {
  HuntOptions o;
  o.first = first;
  o.step = step.value_or(first);
  o.precision = precision.value_or(o.step / 20);
  o.fill_step = fill_step.value_or(o.step / 10);
  o.max = max.value_or(50 * first);
  o.growth = growth;
  check_hunt_options(o);
  return o;
}

std::string_view hunt_reason(HuntPoint::Why why) {
  switch (why) {
    case HuntPoint::Why::trace: return "trace";
    case HuntPoint::Why::bisect: return "bisect";
    case HuntPoint::Why::fill: return "fill";
  }
  return "trace";
}

HuntResult hunt_collapse(const Study& study, std::size_t record, std::size_t variant, const HuntOptions& o) {
  HuntResult h;
  h.record_im = study.record_intensity(record);
  if (!study.can_overturn(variant)) {
    h.fixed_base = true;
    return h;
  }
  // Runs the level; false when the run failed (h.error says why).
  auto run = [&](double level, HuntPoint::Why why) {
    const JobResult r = study.run(study.at_level(record, variant, level));
    ++h.runs;
    if (!r.error.empty()) {
      h.error = r.error;
      return false;
    }
    h.points.push_back({level, past_every_limit(r.run.outcome), why});
    return true;
  };
  auto down_at = [&](double level) { return h.points.back().level == level && h.points.back().overturned; };
  // Bisects (low survives, high overturns) to the precision; returns the
  // final bracket.
  auto bisect = [&](double low, double high) {
    while (high - low > o.precision) {
      const double mid = 0.5 * (low + high);
      if (!(mid > low && mid < high)) break;  // the bracket is as narrow as doubles go
      if (!run(mid, HuntPoint::Why::bisect)) return std::pair{low, high};
      (down_at(mid) ? high : low) = mid;
    }
    return std::pair{low, high};
  };
  // Trace up, the step growing, to --hunt-max itself.
  double low = 0, step = o.step;
  const double tolerance = 1e-9 * o.max;
  for (double level = o.first;; level = decimal(level + step), step *= o.growth) {
    if (level > o.max + tolerance) {
      if (low >= o.max - tolerance) break;  // --hunt-max was the last level run
      level = o.max;
    }
    if (!run(level, HuntPoint::Why::trace)) return h;
    if (down_at(level)) {
      h.collapsed = true;
      h.traced_level = level;
      break;
    }
    low = level;
  }
  // Bracket the trace's collapse; then fill every level below it, or below
  // --hunt-max when the trace met none: a window of overturning that the
  // growing step jumped over is found there.
  double survived = low, collapse = h.traced_level;
  if (h.collapsed) std::tie(survived, collapse) = bisect(low, h.traced_level);
  if (!h.error.empty()) return h;
  const double fill_top = h.collapsed ? survived : o.max;
  for (int k = 1;; ++k) {
    const double level = decimal(o.first + k * o.fill_step);
    if (level >= fill_top - tolerance) break;
    const bool done = std::any_of(h.points.begin(), h.points.end(),
                                  [&](const HuntPoint& p) { return std::abs(p.level - level) <= tolerance; });
    if (!done && !run(level, HuntPoint::Why::fill)) return h;
  }
  auto by_level = [](const HuntPoint& a, const HuntPoint& b) { return a.level < b.level; };
  std::sort(h.points.begin(), h.points.end(), by_level);
  const auto lowest = std::find_if(h.points.begin(), h.points.end(), [](const HuntPoint& p) { return p.overturned; });
  if (lowest == h.points.end()) {  // no level up to --hunt-max overturned at the fill's resolution: censored
    h.survived_level = h.points.back().level;
    return h;
  }
  if (!h.collapsed || lowest->level < collapse) {  // a window below: bracket its lower edge
    h.collapsed = true;
    const double below = lowest == h.points.begin() ? 0 : std::prev(lowest)->level;
    std::tie(survived, collapse) = bisect(below, lowest->level);
    if (!h.error.empty()) return h;
    std::sort(h.points.begin(), h.points.end(), by_level);
  }
  h.collapse_level = collapse;
  h.survived_level = survived;
  for (const HuntPoint& p : h.points) {
    if (p.level <= collapse || p.overturned) continue;
    const bool extends = !h.resurrections.empty() && h.resurrections.back().second == std::prev(&p)->level;
    if (extends) h.resurrections.back().second = p.level;
    else h.resurrections.emplace_back(p.level, p.level);
  }
  return h;
}

Capacity hunt_capacity(const HuntResult& h) {
  return h.collapsed ? Capacity{h.collapse_level, true} : Capacity{h.survived_level, false};
}

std::vector<std::pair<std::size_t, Capacity>> hunt_capacities(const std::vector<HuntResult>& hunts,
                                                              std::size_t variants, std::size_t variant) {
  std::vector<std::pair<std::size_t, Capacity>> out;
  for (std::size_t k = variant; k < hunts.size(); k += variants)
    if (hunts[k].error.empty() && hunts[k].runs > 0) out.emplace_back(k / variants, hunt_capacity(hunts[k]));
  return out;
}

namespace {

// The scene with its lengths scaled by `size`, columns included; no damper.
Scene scaled_block(const Scene& rigid_block, double size) {
  if (!rigid_block.structure.rigid)
    throw InputError(fmt::format("{}: the overturning spectrum needs a rigid block (structure.rigid = true)",
                                 rigid_block.source));
  if (!(size > 0)) throw InputError(fmt::format("block size factor {}: must be positive", size));
  Scene scene = rigid_block;
  scene.structure.half_width *= size;
  scene.structure.heights *= size;
  if (scene.columns) {
    scene.columns->half_width *= size;
    scene.columns->half_height *= size;
    scene.columns->spacing *= size;
  }
  scene.damper.enabled = false;
  return scene;
}

SpectrumScale scale_of(const ContactModel& model) {
  if (model.on_columns) {
    const Columns& c = model.on_columns->columns;
    return {std::sqrt(frame_p2(c)), c.alpha};
  }
  // Housner's frequency parameter p^2 = m g R / J_p, R from the pivot to the
  // centre of gravity (what rocking.report's block summary gives).
  const Structure& st = model.body.structure;
  const double R = std::hypot(st.half_width, centre_of_gravity_height(st));
  return {std::sqrt(model.body.g * total_mass(st) * R / pivot_inertia(st)), slenderness(st)};
}

}  // namespace

SpectrumScale spectrum_scale(const Scene& rigid_block, double size) {
  return scale_of(make_contact_model(scaled_block(rigid_block, size), false));
}

BlockSpectrum overturning_spectrum(const Scene& rigid_block, double size, PulseShape pulse,
                                   const std::vector<double>& frequency_ratios,
                                   const std::vector<double>& amplitude_ratios, int threads,
                                   const std::function<void(std::size_t, std::size_t)>& progress,
                                   const std::vector<std::pair<bool, bool>>& done, const std::function<bool()>& stop) {
  const ContactModel model = make_contact_model(scaled_block(rigid_block, size), false);
  const SpectrumScale scale = scale_of(model);
  BlockSpectrum out;
  out.size = size;
  out.alpha = scale.alpha;
  out.p = scale.p;
  const double a_uplift = model.body.g * std::tan(out.alpha);
  for (double f : frequency_ratios)
    for (double a : amplitude_ratios) {
      SpectrumPoint pt;
      pt.frequency_ratio = f;
      pt.amplitude_ratio = a;
      pt.period_s = 2 * std::numbers::pi / (f * out.p);
      pt.amplitude_g = a * a_uplift / model.body.g;
      out.points.push_back(pt);
    }
  const std::size_t first = std::min(done.size(), out.points.size());
  for (std::size_t i = 0; i < first; ++i) std::tie(out.points[i].uplift, out.points[i].overturned) = done[i];
  out.complete = first + parallel_ordered<SpectrumPoint>(
      out.points.size() - first, threads,
      [&](std::size_t k) {
        SpectrumPoint pt = out.points[first + k];
        const GroundMotion g = GroundMotion::pulse(pulse, pt.amplitude_g * model.body.g, pt.period_s);
        RunOptions o;
        o.duration = g.duration() + 20.0 / out.p;  // time enough to fall after the pulse
        const RunResult r = simulate(model, g, o);
        pt.uplift = r.counts.uplifts > 0;
        pt.overturned = past_every_limit(r.outcome);
        return pt;
      },
      [&](std::size_t k, const SpectrumPoint& pt) { out.points[first + k] = pt; },
      [&](std::size_t n, std::size_t total) {
        if (progress) progress(first + n, first + total);
      },
      stop);
  return out;
}

}  // namespace rocking
