// What a suite study reports (MODEL.md 13): the cells of (record, variant,
// level) hold each job's peaks and whether it overturned; fractiles,
// capacities and stripes are read from them.
module;
#include <nlohmann/json.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>
#include <fmt/format.h>
#include <fmt/ranges.h>
module rocking.study;
import rocking.errors;

namespace rocking {

Limit overturning_limit() { return {"overturning", std::nullopt, 0}; }

std::string study_quantity_names() {
  std::string joints;
  for (const JointQuantityInfo& q : joint_quantity_table)
    if (q.is(Role::study)) joints += fmt::format(", jointK.{}", q.name);
  return fmt::format("{}{}, or DEVICE.elongation, DEVICE.force", quantity_names(Role::study), joints);
}

namespace {
// A name of the schema that is no study quantity (a scalar or a joint's without Role::study) names none.
std::optional<QuantityName> study_quantity(std::string_view text) {
  std::optional<QuantityName> q = parse_quantity_name(text);
  if (q && q->scalar && !info(*q->scalar).is(Role::study)) return std::nullopt;
  if (q && q->joint && !info(q->joint->which).is(Role::study)) return std::nullopt;
  if (q && !q->scalar && !q->joint && !info(q->of).is(Role::study)) return std::nullopt;
  return q;
}

// A joint's peak in a run: NaN when the run's structure has no such joint.
double joint_peak(const RunResult& run, const JointQuantityName& q) {
  const auto j = static_cast<std::size_t>(q.joint);
  if (j >= run.joints.size()) return std::nan("");
  const JointResult& r = run.joints[j];
  switch (q.which) {
    case JointQuantity::theta: return r.peak_theta;
    case JointQuantity::friction: return r.peak_friction;
    case JointQuantity::theta_over_alpha: return r.peak_theta_over_alpha;
    default: return std::nan("");  // no peak tracked (not a study quantity)
  }
}
}  // namespace

QuantityName parse_study_quantity(std::string_view text) {
  const std::optional<QuantityName> q = study_quantity(text);
  if (!q) throw InputError(fmt::format("unknown quantity '{}' (choose from {})", text, study_quantity_names()));
  return *q;
}

Limit parse_limit(const std::string& text) {
  const auto eq = text.find('=');
  const std::string key = text.substr(0, eq);
  const std::optional<QuantityName> quantity = study_quantity(key);
  if (eq == std::string::npos || !quantity)
    throw InputError(fmt::format("--limit '{}': expected QUANTITY=VALUE with QUANTITY one of {} (e.g. "
                                 "theta_over_alpha=0.5, joint1.theta_over_alpha=0.5, damper_d=0.07, "
                                 "plates.elongation=0.07)",
                                 text, study_quantity_names()));
  const std::string number = text.substr(eq + 1);
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != number.size() || !(value > 0) || !std::isfinite(value))
    throw InputError(fmt::format("--limit '{}': '{}' is not a positive number", text, number));
  return {fmt::format("{}>={:g}", key, value), quantity, value};
}

void check_limit(const Study& study, const Limit& limit) {
  if (!limit.quantity || limit.quantity->scalar) return;
  if (limit.quantity->joint) {
    int joints = 0;  // the most joints above the base of any variant
    for (std::size_t v = 0; v < study.variants().size(); ++v) joints = std::max(joints, study.joints(v));
    if (limit.quantity->joint->joint > joints)
      throw InputError(fmt::format("--limit '{}': no joint {} in the study's scene ({})", limit.name,
                                   limit.quantity->joint->joint,
                                   joints == 0 ? "it has no [[joint]] above its base"
                                               : fmt::format("its joints above the base are 1 to {}", joints)));
    return;
  }
  const std::vector<std::string> names = study_columns(study).devices;  // every variant's, in order
  if (std::ranges::find(names, limit.quantity->device) == names.end())
    throw InputError(fmt::format("--limit '{}': no device '{}' in the study's scene (devices: {})", limit.name,
                                 limit.quantity->device, names.empty() ? "none" : fmt::format("{}", fmt::join(names, ", "))));
}

std::vector<QuantityName> StudyColumns::all() const {
  std::vector<QuantityName> out;
  for (Quantity q : quantities) out.emplace_back(q);
  for (const JointQuantityName& j : joints) out.emplace_back(j);
  for (const std::string& d : devices)
    for (const DeviceQuantityInfo& i : device_quantity_table)
      if (i.is(Role::study)) out.emplace_back(d, i.id);
  return out;
}

std::vector<std::string> StudyColumns::names() const {
  std::vector<std::string> out;
  for (const QuantityName& q : all()) out.push_back(q.name());
  return out;
}

std::vector<double> StudyColumns::values(const RunResult& run) const {
  std::vector<double> out;
  out.reserve(size());
  for (Quantity q : quantities) out.push_back(run.reports(q) ? run.peak(q) : std::nan(""));
  for (const JointQuantityName& j : joints) out.push_back(joint_peak(run, j));
  for (const std::string& d : devices) {
    const auto it = std::ranges::find(run.devices, d, &DeviceResult::name);
    for (const DeviceQuantityInfo& i : device_quantity_table) {
      if (!i.is(Role::study)) continue;
      if (it == run.devices.end()) out.push_back(std::nan(""));
      else if (i.id == DeviceQuantity::elongation) out.push_back(it->peak_elongation);
      else if (i.id == DeviceQuantity::force) out.push_back(it->peak_force);
      else out.push_back(std::nan(""));  // a study quantity with no peak here: none is one today
    }
  }
  return out;
}

std::optional<std::size_t> StudyColumns::index(const QuantityName& q) const {
  if (q.scalar) {
    const auto at = std::ranges::find(quantities, *q.scalar);
    if (at == quantities.end()) return std::nullopt;
    return static_cast<std::size_t>(at - quantities.begin());
  }
  if (q.joint) {
    const auto at = std::ranges::find(joints, *q.joint);
    if (at == joints.end()) return std::nullopt;
    return quantities.size() + static_cast<std::size_t>(at - joints.begin());
  }
  const auto at = std::ranges::find(devices, q.device);
  if (at == devices.end() || !info(q.of).is(Role::study)) return std::nullopt;
  return quantities.size() + joints.size() + device_study_count * static_cast<std::size_t>(at - devices.begin()) +
         device_study_position(q.of);
}

double StudyRow::value(const StudyColumns& columns, const QuantityName& q) const {
  const std::optional<std::size_t> k = columns.index(q);
  return k && *k < values.size() ? values[*k] : std::nan("");
}

StudyRow study_row(const StudyColumns& columns, const Job& job, const JobResult& result) {
  StudyRow row;
  row.level = job.level;
  row.ran = result.error.empty();
  row.outcome = result.run.outcome;
  if (row.ran) row.values = columns.values(result.run);
  return row;
}

StudyColumns study_columns(const Study& study) {
  StudyColumns c;
  for (Quantity q : study_quantities)  // those some variant reports (no damper_d without the paper's dampers)
    for (std::size_t v = 0; v < study.variants().size(); ++v)
      if (study.reports(v, q)) {
        c.quantities.push_back(q);
        break;
      }
  int joints = 0;
  for (std::size_t v = 0; v < study.variants().size(); ++v) joints = std::max(joints, study.joints(v));
  for (int j = 1; j <= joints; ++j)
    for (std::size_t k = 0; k < joint_quantity_count; ++k)
      if (joint_quantity_table[k].is(Role::study)) c.joints.push_back({j, static_cast<JointQuantity>(k)});
  for (std::size_t v = 0; v < study.variants().size(); ++v)
    for (const std::string& d : study.device_names(v))
      if (std::ranges::find(c.devices, d) == c.devices.end()) c.devices.push_back(d);
  return c;
}

Resurrection parse_resurrection(std::string_view text) {
  if (text == "first") return Resurrection::first;
  if (text == "keep") return Resurrection::keep;
  throw InputError(fmt::format("--resurrection '{}': choose first (a record is collapsed from its first overturning "
                               "on) or keep (each level counts as it ran)",
                               text));
}

StudySummary::StudySummary(const Study& study, std::vector<double> levels, std::vector<Limit> limits,
                           Resurrection resurrection)
    : records_(study.records().size()), variants_(study.variants().size()), levels_(std::move(levels)),
      limits_(std::move(limits)), resurrection_(resurrection), columns_(study_columns(study)) {
  std::sort(levels_.begin(), levels_.end());
  levels_.erase(std::unique(levels_.begin(), levels_.end()), levels_.end());
  cells_.resize(records_ * variants_ * levels_.size());
}

void StudySummary::add(const Job& job, const JobResult& result) { add(job, study_row(columns_, job, result)); }

void StudySummary::add(const Job& job, const StudyRow& row) {
  if (!row.ran) return;
  const auto at = std::lower_bound(levels_.begin(), levels_.end(), job.level);
  if (at == levels_.end() || *at != job.level) return;  // not a level of this summary
  Cell& c = cells_[(job.record * variants_ + job.variant) * levels_.size() + static_cast<std::size_t>(at - levels_.begin())];
  c.ran = true;
  c.row = row;
}

// A quantity the run does not report (NaN) never reaches a limit.
bool StudySummary::reached(const Cell& c, const Limit& l) const {
  return c.row.collapsed() || (l.quantity && value(c, *l.quantity) >= l.value);
}

std::vector<StudySummary::FractileRow> StudySummary::fractiles(std::size_t variant, const QuantityName& q) const {
  std::vector<FractileRow> rows;
  const auto overturned_at = limit_table(variant, overturning_limit());  // by the convention
  for (std::size_t k = 0; k < levels_.size(); ++k) {
    FractileRow row;
    row.level = levels_[k];
    std::vector<double> edp;
    for (std::size_t r = 0; r < records_; ++r) {
      const Cell& c = cell(r, variant, k);
      if (!c.ran) continue;
      const bool overturned = overturned_at[r][k] == 1;
      const double v = overturned ? std::numeric_limits<double>::infinity() : value(c, q);
      if (std::isnan(v)) continue;  // not reported by this variant
      row.collapsed += overturned ? 1 : 0;
      edp.push_back(v);
    }
    row.runs = edp.size();
    if (edp.empty()) continue;
    const double p[] = {0.16, 0.5, 0.84};
    for (std::size_t i = 0; i < 3; ++i) row.edp[i] = fractile(edp, p[i]);
    rows.push_back(row);
  }
  return rows;
}

StudySummary::Curve StudySummary::curve(std::size_t record, std::size_t variant, const QuantityName& q) const {
  Curve out;
  for (std::size_t k = 0; k < levels_.size(); ++k) {
    const Cell& c = cell(record, variant, k);
    if (!c.ran) continue;
    if (c.row.collapsed()) {
      out.collapse_level = levels_[k];
      break;
    }
    if (const double v = value(c, q); !std::isnan(v)) out.points.emplace_back(levels_[k], v);
  }
  return out;
}

std::vector<std::pair<std::size_t, Capacity>> StudySummary::capacities(std::size_t variant, std::size_t limit) const {
  std::vector<std::pair<std::size_t, Capacity>> out;
  for (std::size_t r = 0; r < records_; ++r) {
    std::optional<Capacity> cap;
    for (std::size_t k = 0; k < levels_.size(); ++k) {
      const Cell& c = cell(r, variant, k);
      if (!c.ran) continue;
      if (reached(c, limits_[limit])) {
        cap = Capacity{levels_[k], true};
        break;
      }
      cap = Capacity{levels_[k], false};
    }
    if (cap) out.emplace_back(r, *cap);
  }
  return out;
}

std::vector<std::vector<signed char>> StudySummary::limit_table(std::size_t variant, const Limit& limit) const {
  std::vector<std::vector<signed char>> t(records_, std::vector<signed char>(levels_.size(), -1));
  for (std::size_t r = 0; r < records_; ++r) {
    bool once = false;
    for (std::size_t k = 0; k < levels_.size(); ++k) {
      const Cell& c = cell(r, variant, k);
      if (!c.ran) continue;
      const bool now = reached(c, limit);
      once = once || now;
      t[r][k] = (resurrection_ == Resurrection::first ? once : now) ? 1 : 0;
    }
  }
  return t;
}

std::vector<Stripe> StudySummary::stripes_of(const std::vector<std::vector<signed char>>& table,
                                             const std::vector<std::size_t>& records) const {
  std::vector<Stripe> out;
  for (std::size_t k = 0; k < levels_.size(); ++k) {
    Stripe s{levels_[k], 0, 0};
    for (std::size_t r : records) {
      if (table[r][k] < 0) continue;
      ++s.runs;
      s.reached += static_cast<std::size_t>(table[r][k]);
    }
    if (s.runs > 0) out.push_back(s);
  }
  return out;
}

std::vector<Stripe> StudySummary::stripes(std::size_t variant, std::size_t limit) const {
  std::vector<std::size_t> every(records_);
  for (std::size_t r = 0; r < records_; ++r) every[r] = r;
  return stripes_of(limit_table(variant, limits_.at(limit)), every);
}

void check_fragility_options(const FragilityOptions& o) {
  check_bootstrap_options(o.bootstrap);
  total_beta(0, o.beta_modelling);
}

nlohmann::json fit_json(const LognormalFit& f, const FitBootstrap& b, double beta_modelling) {
  nlohmann::json j{{"method", f.method}, {"fitted", f.fitted}, {"records", f.records}, {"reached", f.reached},
                   {"note", f.note}};
  if (!f.fitted) return j;
  j["median"] = f.median;
  j["beta"] = f.beta;
  j["log_median_se"] = f.log_median_se;
  j["beta_se"] = f.beta_se;
  j["beta_modelling"] = beta_modelling;
  j["beta_total"] = total_beta(f.beta, beta_modelling);
  if (b.draws == 0) return j;
  j["bootstrap"] = {{"draws", b.draws}, {"fitted", b.fitted}, {"level", b.level}, {"seed", b.seed}};
  if (!b.computed()) return j;
  j["median_interval"] = b.median;
  j["beta_interval"] = b.beta;
  j["beta_total_interval"] = {total_beta(b.beta[0], beta_modelling), total_beta(b.beta[1], beta_modelling)};
  return j;
}

nlohmann::json fragility_json(const LimitFragility& f, const std::vector<std::string>& ids) {
  nlohmann::json jc = nlohmann::json::array(), js = nlohmann::json::array();
  for (const auto& [r, c] : f.capacities) jc.push_back({{"record", ids.at(r)}, {"level", c.im}, {"reached", c.reached}});
  for (const Stripe& s : f.stripes) js.push_back({{"level", s.im}, {"runs", s.runs}, {"reached", s.reached}});
  nlohmann::json j{{"limit", f.limit.name},
                   {"capacity_fit", fit_json(f.capacity_fit, f.capacity_bootstrap, f.beta_modelling)},
                   {"capacities", jc}};
  if (f.stripes_fit.method.empty()) return j;  // capacities alone
  j["stripes_fit"] = fit_json(f.stripes_fit, f.stripes_bootstrap, f.beta_modelling);
  j["stripes"] = js;
  return j;
}

LimitFragility capacity_fragility(const Limit& limit, std::vector<std::pair<std::size_t, Capacity>> capacities,
                                  const FragilityOptions& options) {
  check_fragility_options(options);
  LimitFragility f;
  f.limit = limit;
  f.beta_modelling = options.beta_modelling;
  f.capacities = std::move(capacities);
  std::vector<Capacity> values;
  for (const auto& c : f.capacities) values.push_back(c.second);
  f.capacity_fit = fit_capacities(values);
  if (options.bootstrap.draws > 0)
    f.capacity_bootstrap = bootstrap_fit(values.size(), [&](const std::vector<std::size_t>& sample) {
      std::vector<Capacity> s;
      s.reserve(sample.size());
      for (std::size_t i : sample) s.push_back(values[i]);
      return fit_capacities(s, &f.capacity_fit);
    }, options.bootstrap);
  return f;
}

LimitFragility StudySummary::fragility(std::size_t variant, std::size_t limit, const FragilityOptions& options) const {
  LimitFragility f = capacity_fragility(limits_.at(limit), capacities(variant, limit), options);
  f.stripes = stripes(variant, limit);
  f.stripes_fit = fit_stripes(f.stripes);
  if (options.bootstrap.draws == 0) return f;
  std::vector<std::size_t> ran;  // the records that ran, which the bootstrap resamples
  for (const auto& c : f.capacities) ran.push_back(c.first);
  const auto table = limit_table(variant, limits_.at(limit));
  f.stripes_bootstrap = bootstrap_fit(ran.size(), [&](const std::vector<std::size_t>& sample) {
    std::vector<std::size_t> records;
    records.reserve(sample.size());
    for (std::size_t i : sample) records.push_back(ran[i]);
    return fit_stripes(stripes_of(table, records), &f.stripes_fit);
  }, options.bootstrap);
  return f;
}

std::vector<StudySummary::Resurrections> StudySummary::resurrections(std::size_t variant) const {
  std::vector<Resurrections> out;
  for (std::size_t r = 0; r < records_; ++r) {
    std::optional<Resurrections> rec;
    for (std::size_t k = 0; k < levels_.size(); ++k) {
      const Cell& c = cell(r, variant, k);
      if (!c.ran) continue;
      if (!rec && c.row.collapsed()) rec = Resurrections{r, levels_[k], {}};
      else if (rec && !c.row.collapsed()) rec->survived.push_back(levels_[k]);
    }
    if (rec && !rec->survived.empty()) out.push_back(*rec);
  }
  return out;
}

}  // namespace rocking
