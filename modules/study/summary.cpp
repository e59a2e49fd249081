// What a suite study reports (MODEL.md 13): the cells of (record, variant,
// level) hold each job's peaks and whether it overturned; fractiles,
// capacities and stripes are read from them.
module;
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>
#include <fmt/format.h>
module rocking.study;
import rocking.errors;

namespace rocking {

Limit overturning_limit() { return {"overturning", std::nullopt, 0}; }

std::optional<Quantity> study_quantity(std::string_view name) {
  for (Quantity q : study_quantities)
    if (name == quantity_name(q)) return q;
  return std::nullopt;
}

std::string study_quantity_names() {
  std::string names;
  for (Quantity q : study_quantities) names += (names.empty() ? "" : ", ") + std::string(quantity_name(q));
  return names;
}

Limit parse_limit(const std::string& text) {
  const auto eq = text.find('=');
  const std::string key = text.substr(0, eq);
  const std::optional<Quantity> quantity = study_quantity(key);
  if (eq == std::string::npos || !quantity)
    throw InputError(fmt::format("--limit '{}': expected QUANTITY=VALUE with QUANTITY one of {} (e.g. "
                                 "theta_over_alpha=0.5, damper_d=0.07)",
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

StudySummary::StudySummary(const Study& study, std::vector<double> levels, std::vector<Limit> limits)
    : records_(study.records().size()), variants_(study.variants().size()), levels_(std::move(levels)),
      limits_(std::move(limits)) {
  std::sort(levels_.begin(), levels_.end());
  levels_.erase(std::unique(levels_.begin(), levels_.end()), levels_.end());
  cells_.resize(records_ * variants_ * levels_.size());
}

void StudySummary::add(const Job& job, const JobResult& result) {
  if (!result.error.empty()) return;
  const auto at = std::lower_bound(levels_.begin(), levels_.end(), job.level);
  if (at == levels_.end() || *at != job.level) return;  // not a level of this summary
  Cell& c = cells_[(job.record * variants_ + job.variant) * levels_.size() + static_cast<std::size_t>(at - levels_.begin())];
  c.ran = true;
  c.overturned = result.run.outcome == Outcome::overturned;
  c.peaks = result.run.peaks;
}

bool StudySummary::reached(const Cell& c, const Limit& l) const {
  return c.overturned || (l.quantity && c.peaks[static_cast<std::size_t>(*l.quantity)] >= l.value);
}

std::vector<StudySummary::FractileRow> StudySummary::fractiles(std::size_t variant, Quantity q) const {
  std::vector<FractileRow> rows;
  for (std::size_t k = 0; k < levels_.size(); ++k) {
    FractileRow row;
    row.level = levels_[k];
    std::vector<double> edp;
    for (std::size_t r = 0; r < records_; ++r) {
      const Cell& c = cell(r, variant, k);
      if (!c.ran) continue;
      row.collapsed += c.overturned ? 1 : 0;
      edp.push_back(c.overturned ? std::numeric_limits<double>::infinity() : c.peaks[static_cast<std::size_t>(q)]);
    }
    row.runs = edp.size();
    if (edp.empty()) continue;
    const double p[] = {0.16, 0.5, 0.84};
    for (std::size_t i = 0; i < 3; ++i) row.edp[i] = fractile(edp, p[i]);
    rows.push_back(row);
  }
  return rows;
}

StudySummary::Curve StudySummary::curve(std::size_t record, std::size_t variant, Quantity q) const {
  Curve out;
  for (std::size_t k = 0; k < levels_.size(); ++k) {
    const Cell& c = cell(record, variant, k);
    if (!c.ran) continue;
    if (c.overturned) {
      out.collapse_level = levels_[k];
      break;
    }
    out.points.emplace_back(levels_[k], c.peaks[static_cast<std::size_t>(q)]);
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

std::vector<Stripe> StudySummary::stripes(std::size_t variant, std::size_t limit) const {
  std::vector<Stripe> out;
  for (std::size_t k = 0; k < levels_.size(); ++k) {
    Stripe s{levels_[k], 0, 0};
    for (std::size_t r = 0; r < records_; ++r) {
      const Cell& c = cell(r, variant, k);
      if (!c.ran) continue;
      ++s.runs;
      s.reached += reached(c, limits_[limit]) ? 1 : 0;
    }
    if (s.runs > 0) out.push_back(s);
  }
  return out;
}

}  // namespace rocking
