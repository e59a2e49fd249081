module;
#include <rocking/eigen.hpp>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>
#include <fmt/format.h>
module rocking.study;
import rocking.errors;

namespace rocking {

Variant named_variant(const std::string& name) {
  if (name == "scene") return {name, {}};
  if (name == "damper") return {name, {"damper.enabled=true"}};
  if (name == "no-damper") return {name, {"damper.enabled=false"}};
  if (name == "fixed-base") return {name, {"contact.rocking=false"}};
  throw InputError(fmt::format("unknown variant '{}' (choose from damper, no-damper, fixed-base, scene)", name));
}

Study::Study(const std::string& scene_path, const std::vector<std::string>& common_overrides,
             std::vector<std::string> records, RecordOptions record_options, std::vector<Variant> variants,
             RunOptions run_options)
    : records_(std::move(records)), variants_(std::move(variants)), options_(run_options) {
  options_.track_energy = false;
  for (const std::string& r : records_) {
    try {
      motions_.emplace_back(read_record(r, record_options));
      record_errors_.emplace_back();
    } catch (const InputError& e) {
      motions_.emplace_back(std::nullopt);
      record_errors_.emplace_back(e.what());
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

std::vector<Job> Study::ladder(const std::vector<double>& scales) const {
  std::vector<Job> jobs;
  for (std::size_t r = 0; r < records_.size(); ++r)
    for (double s : scales)
      for (std::size_t v = 0; v < variants_.size(); ++v) jobs.push_back({r, s, v});
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
  out.run = simulate(*models_[job.variant], motions_[job.record]->scaled(job.scale), options_);
  if (out.run.outcome == Outcome::failed) out.error = out.run.failure;
  return out;
}

bool Study::can_overturn(std::size_t variant) const {
  return !models_[variant] || models_[variant]->kind != ModelKind::fixed_base;
}

bool Study::has_damper(std::size_t variant) const { return models_[variant] && models_[variant]->has_damper; }

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
    if (!(step > 0) || last < first || (last - first) / step > 1e6) fail();
    const auto n = static_cast<long>(std::floor((last - first) / step + 1e-9));
    for (long i = 0; i <= n; ++i) out.push_back(first + static_cast<double>(i) * step);
  } else {
    if (text.ends_with(",")) fail();
    std::stringstream ss(text);
    for (std::string p; std::getline(ss, p, ',');) out.push_back(number(p));
  }
  if (out.empty()) fail();
  return out;
}

HuntResult hunt_collapse(const Study& study, std::size_t record, std::size_t variant, double first, double step,
                         double max_scale, double precision) {
  HuntResult h;
  if (!study.can_overturn(variant)) {
    h.fixed_base = true;
    return h;
  }
  auto overturns = [&](double scale, bool& failed) {
    const JobResult r = study.run({record, scale, variant});
    ++h.runs;
    if (!r.error.empty()) {
      h.error = r.error;
      failed = true;
      return false;
    }
    return r.run.outcome == Outcome::overturned;
  };
  bool failed = false;
  double low = 0, high = 0;
  for (double s = first; s <= max_scale + 1e-12; s += step) {
    const bool down = overturns(s, failed);
    if (failed) return h;
    if (down) {
      h.collapsed = true;
      high = s;
      break;
    }
    low = s;
  }
  if (!h.collapsed) {
    h.survived_scale = low;
    return h;
  }
  while (high - low > precision) {
    const double mid = 0.5 * (low + high);
    const bool down = overturns(mid, failed);
    if (failed) return h;
    (down ? high : low) = mid;
  }
  h.collapse_scale = high;
  h.survived_scale = low;
  return h;
}

BlockSpectrum overturning_spectrum(const Scene& rigid_block, double size, PulseShape pulse,
                                   const std::vector<double>& frequency_ratios,
                                   const std::vector<double>& amplitude_ratios, int threads,
                                   const std::function<void(std::size_t, std::size_t)>& progress) {
  if (!rigid_block.structure.rigid)
    throw InputError(fmt::format("{}: the overturning spectrum needs a rigid block (structure.rigid = true)",
                                 rigid_block.source));
  if (!(size > 0)) throw InputError(fmt::format("block size factor {}: must be positive", size));
  Scene scene = rigid_block;
  scene.structure.half_width *= size;
  scene.structure.heights *= size;
  scene.damper.enabled = false;
  const ContactModel model = make_contact_model(scene, false);
  const Structure& st = model.body.structure;
  BlockSpectrum out;
  out.size = size;
  out.alpha = slenderness(st);
  out.p = std::sqrt(model.body.g * st.heights.dot(st.masses) / pivot_inertia(st));
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
  parallel_ordered<SpectrumPoint>(
      out.points.size(), threads,
      [&](std::size_t i) {
        SpectrumPoint pt = out.points[i];
        const GroundMotion g = GroundMotion::pulse(pulse, pt.amplitude_g * model.body.g, pt.period_s);
        RunOptions o;
        o.duration = g.duration() + 20.0 / out.p;  // time enough to fall after the pulse
        const RunResult r = simulate(model, g, o);
        pt.uplift = r.counts.uplifts > 0;
        pt.overturned = r.outcome == Outcome::overturned;
        return pt;
      },
      [&](std::size_t i, const SpectrumPoint& pt) { out.points[i] = pt; }, progress);
  return out;
}

}  // namespace rocking
