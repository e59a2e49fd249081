// Suite figures of `rocking ida` and `rocking sweep` (MODEL.md 13): the
// numbers come from rocking.study's StudySummary and rocking.fragility (their
// files from rocking.study_files); this file draws them.
#include "study_report.hpp"
#include "run_output.hpp"
#include <nlohmann/json.hpp>
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>
import rocking.study_files;
import rocking.study;
import rocking.plot;

namespace rocking::app {

namespace fs = std::filesystem;

namespace {

// The marker of variant v's fitted curves (filled: the data points are open
// circles and squares): the variants read apart in greyscale print.
int variant_marker(std::size_t v) {
  static constexpr int filled[] = {7, 5, 9, 11, 13};
  return filled[v % std::size(filled)];
}

bool any_modelling(const SuiteFragility& fragility) {
  for (const auto& v : fragility)
    for (const auto& f : v)
      if (f && f->beta_modelling > 0) return true;
  return false;
}

// A limit state in words: "overturning", "rocking angle over alpha_cg >= 0.5".
std::string limit_title(const Limit& limit) {
  if (!limit.quantity) return limit.name;
  const QuantityName& q = *limit.quantity;
  const double factor = figure_factor(q);
  const std::string unit(q.scalar  ? info(*q.scalar).figure_unit
                         : q.joint ? info(q.joint->which).figure_unit
                                   : info(q.of).figure_unit);
  const std::string words =
      q.scalar  ? std::string(axis_words(info(*q.scalar).words))
      : q.joint ? fmt::format("joint {}: {}", q.joint->joint, axis_words(info(q.joint->which).words))
                : q.device + " " + std::string(axis_words(info(q.of).words));
  return fmt::format("{} ≥ {:g}{}", words, limit.value * factor, unit == "-" ? "" : " " + unit);
}

}  // namespace

std::string im_words(const IntensityMeasure& im) {
  const std::string damping = fmt::format("{:g} %", im.damping * 100);
  switch (im.kind) {
    case IntensityMeasure::Kind::scale_factor: return "the scale factor on the record";
    case IntensityMeasure::Kind::pga: return "PGA";
    case IntensityMeasure::Kind::pgv: return "PGV";
    case IntensityMeasure::Kind::sa: return fmt::format("Sa({:.3g} s), {}", im.t1, damping);
    case IntensityMeasure::Kind::saavg: return fmt::format("Sa,avg({:.3g}-{:.3g} s), {}", im.t1, im.t2, damping);
    case IntensityMeasure::Kind::rotd50: return fmt::format("RotD50 Sa({:.3g} s), {}", im.t1, damping);
    case IntensityMeasure::Kind::rotd100: return fmt::format("RotD100 Sa({:.3g} s), {}", im.t1, damping);
  }
  return im.name();
}

std::string im_axis_label(const IntensityMeasure& im) {
  const std::string damping = im.damping == 0.05 ? "" : fmt::format(", {:g} %", im.damping * 100);
  switch (im.kind) {
    case IntensityMeasure::Kind::scale_factor: return "scale factor on the record [-]";
    case IntensityMeasure::Kind::pga: return "PGA [g]";
    case IntensityMeasure::Kind::pgv: return "PGV [m/s]";
    case IntensityMeasure::Kind::sa: return fmt::format("S_a({:.3g} s{}) [g]", im.t1, damping);
    case IntensityMeasure::Kind::saavg: return fmt::format("S_{{a,avg}}({:.3g}-{:.3g} s{}) [g]", im.t1, im.t2, damping);
    case IntensityMeasure::Kind::rotd50: return fmt::format("RotD50 S_a({:.3g} s{}) [g]", im.t1, damping);
    case IntensityMeasure::Kind::rotd100: return fmt::format("RotD100 S_a({:.3g} s{}) [g]", im.t1, damping);
  }
  return im.name();
}

namespace {

// What every figure of a ladder's report shares: the study, its summary and
// fragility, where the data goes, and the figures' size on the page.
struct LadderReport {
  const fs::path& dir;
  const Study& st;
  const StudySummary& summary;
  const SuiteFragility& fragility_of;
  const std::string& kind;
  const std::string& scene_name;
  const std::vector<std::string>& formats;
  const IntensityMeasure& im = st.intensity_measure();
  const std::string data = kind + "_suite.data";
  const std::size_t nv = st.variants().size();
  const std::size_t nr = st.records().size();
  const int cols = static_cast<int>(std::min<std::size_t>(nv, 3));
  const int rows = static_cast<int>((nv + 2) / 3);
  // The top of the fragility axes: the highest level and a tenth.
  const double top = summary.levels().empty() ? 1 : summary.levels().back() * 1.1;

  plot::Figure figure(const std::string& name, const std::string& title) const {
    plot::Figure fig;
    fig.dir = dir;
    fig.name = name;
    fig.title = title;
    fig.formats = formats;
    fig.width = 560 * cols + 120;
    fig.height = 470 * rows + 200;
    return fig;
  }
  // The fitted CDF (the capacity fit with its total dispersion) at 200
  // levels up to the top of the axis.
  std::string fit_curve(const LognormalFit& f, double beta_modelling) const {
    std::string text = "im,p\n";
    if (f.fitted)
      for (int k = 1; k <= 200; ++k) {
        const double x = top * k / 200.0;
        text += fmt::format("{:.6g},{:.6g}\n", x, lognormal_cdf(x, f.median, total_beta(f.beta, beta_modelling)));
      }
    return text;
  }
  // Its bootstrap band at the same levels.
  std::string band(const FitBootstrap& b, double beta_modelling) const {
    std::string text = "im,low,high\n";
    if (b.computed())
      for (int k = 1; k <= 200; ++k) {
        const double x = top * k / 200.0;
        const auto [low, high] = cdf_band(b, x, beta_modelling);
        text += fmt::format("{:.6g},{:.6g},{:.6g}\n", x, low, high);
      }
    return text;
  }
  // "90 % interval" (the bootstrap's level), or nothing without fragility.
  std::string interval_words() const {
    return fragility_of.empty() || fragility_of[0].empty() || !fragility_of[0][0]
               ? std::string()
               : fmt::format("{:g} % interval", fragility_of[0][0]->capacity_bootstrap.level * 100);
  }
  // Whether any fragility has a bootstrap band.
  bool banded() const {
    for (const auto& v : fragility_of)
      for (const auto& f : v)
        if (f && f->capacity_bootstrap.computed()) return true;
    return false;
  }

  void ida_curves(std::vector<fs::path>& written) const;
  void fragility(std::vector<fs::path>& written) const;
  void damage_states(std::vector<fs::path>& written) const;
};

// IDA curves: one figure per scalar study quantity (the devices' are in
// summary.csv), a panel per variant, thin per record, bold fractiles.
void LadderReport::ida_curves(std::vector<fs::path>& written) const {
  using Style = plot::Line::Style;
  // One figure per scalar study quantity (the devices' are in summary.csv).
  for (Quantity quantity : study_quantities) {
    const QuantityName axis_q(quantity);
    const std::string q(info(quantity).name);
    const double factor = figure_factor(axis_q);
    auto shows = [&](std::size_t v) { return st.reports(v, axis_q); };
    double x_max = 0;
    for (std::size_t v = 0; v < nv; ++v)
      if (shows(v))
        for (std::size_t r = 0; r < nr; ++r)
          for (const auto& [level, peak] : summary.curve(r, v, axis_q).points) x_max = std::max(x_max, peak * factor);
    if (!(x_max > 0)) continue;
    x_max *= 1.05;
    std::vector<plot::LinePanel> panels;
    for (std::size_t v = 0; v < nv; ++v) {
      plot::LinePanel panel{variant_label(st.variants()[v].name), {}, "0:*", fmt::format("0:{:.6g}", x_max)};
      if (!shows(v)) {
        panels.push_back(panel);
        continue;
      }
      const std::string stem = fmt::format("{}/{}_{}", data, q, v);
      std::string curves = "edp,level\n", crosses = "edp,level\n";
      for (std::size_t r = 0; r < nr; ++r) {
        const StudySummary::Curve c = summary.curve(r, v, axis_q);
        for (const auto& [level, peak] : c.points) curves += fmt::format("{:.6g},{:.6g}\n", peak * factor, level);
        if (!std::isnan(c.collapse_level)) {
          // Flat from the last survivor (V&C's flatline), the overturning crossed above it.
          const double x = c.points.empty() ? 0 : c.points.back().second * factor;
          if (!c.points.empty()) curves += fmt::format("{:.6g},{:.6g}\n", x_max, c.points.back().first);
          crosses += fmt::format("{:.6g},{:.6g}\n", x, c.collapse_level);
        }
        curves += "\n";
      }
      write_text(dir / (stem + "_records.csv"), curves);
      write_text(dir / (stem + "_overturns.csv"), crosses);
      panel.lines.push_back({Style::thin_grey, "each record", stem + "_records.csv", 0, 0, 0, {"edp", "level"}});
      panel.lines.push_back({Style::crosses, "overturns (x)", stem + "_overturns.csv", 5, 0, 0, {"edp", "level"}});
      const auto rows_f = summary.fractiles(v, axis_q);
      const char* names[] = {"16", "50", "84"};
      for (std::size_t i = 0; i < 3; ++i) {
        std::string text = "edp,level\n";
        double last_level = 0, last_x = 0;
        bool finite = false;
        for (const auto& row : rows_f) {
          if (std::isinf(row.edp[i])) {
            if (finite) text += fmt::format("{:.6g},{:.6g}\n", x_max, last_level);  // the fractile collapses
            break;
          }
          last_level = row.level;
          last_x = row.edp[i] * factor;
          finite = true;
          text += fmt::format("{:.6g},{:.6g}\n", last_x, last_level);
        }
        const std::string file = fmt::format("{}_p{}.csv", stem, names[i]);
        write_text(dir / file, text);
        // Told apart in greyscale: 50 % solid, 16 % dashed, 84 % dotted.
        panel.lines.push_back({Style::bold, fmt::format("{} % fractile", names[i]), file, i == 1 ? 0 : 1,
                               i == 1 ? 0 : i == 0 ? 1 : 2, 0, {"edp", "level"}});
      }
      panels.push_back(panel);
    }
    const plot::Figure fig = figure(
        fmt::format("{}_{}", kind, q),
        fmt::format("{}: IDA curves over {} records, by {}\n(thin: each record; bold: fractiles, flat where they "
                    "overturn)",
                    scene_name, nr, im_words(im)));
    for (const fs::path& f : plot::render_lines(fig, rows, cols, "peak " + axis_label(axis_q), im_axis_label(im), panels)) written.push_back(f);
  }
}

// Fragility: one panel per limit state, one colour per variant.
void LadderReport::fragility(std::vector<fs::path>& written) const {
  using Style = plot::Line::Style;
  const std::string interval_words = this->interval_words();
  std::vector<plot::LinePanel> panels;
  bool banded = false;
  std::vector<bool> keyed(nv, false);
  for (std::size_t l = 0; l < summary.limits().size(); ++l) {
    const Limit& limit = summary.limits()[l];
    plot::LinePanel panel{"limit state: " + limit_title(limit), {}, "0:1.02", fmt::format("0:{:.6g}", top)};
    for (std::size_t v = 0; v < nv; ++v) {
      if (!fragility_of[v][l]) continue;
      const LimitFragility& f = *fragility_of[v][l];
      const std::string label = variant_label(st.variants()[v].name);
      const std::string stem = fmt::format("{}/fragility_{}_{}", data, l, v);
      std::vector<double> reached;
      for (const auto& [r, c] : f.capacities)
        if (c.reached) reached.push_back(c.im);
      std::sort(reached.begin(), reached.end());
      std::string ecdf = "im,p\n", stripe_text = "im,p\n";
      for (std::size_t k = 0; k < reached.size(); ++k)
        ecdf += fmt::format("{:.6g},{:.6g}\n", reached[k],
                            static_cast<double>(k + 1) / static_cast<double>(f.capacities.size()));
      for (const Stripe& s : f.stripes)
        stripe_text += fmt::format("{:.6g},{:.6g}\n", s.im, static_cast<double>(s.reached) / static_cast<double>(s.runs));
      write_text(dir / (stem + "_records.csv"), ecdf);
      write_text(dir / (stem + "_stripes.csv"), stripe_text);
      write_text(dir / (stem + "_fit.csv"), fit_curve(f.capacity_fit, f.beta_modelling));
      write_text(dir / (stem + "_band.csv"), band(f.capacity_bootstrap, f.beta_modelling));
      write_text(dir / (stem + "_stripes_fit.csv"), fit_curve(f.stripes_fit, 0));
      const int colour = static_cast<int>(v), marker = variant_marker(v);
      if (f.capacity_bootstrap.computed())
        panel.lines.push_back({Style::band, "", stem + "_band.csv", colour, 0, 0, {"im", "low", "high"}});
      panel.lines.push_back({Style::bold, "", stem + "_fit.csv", colour, 0, marker, {"im", "p"}});
      panel.lines.push_back({Style::circles, "", stem + "_records.csv", colour, 0, 0, {"im", "p"}});
      panel.lines.push_back({Style::squares, "", stem + "_stripes.csv", colour, 0, 0, {"im", "p"}});
      panel.lines.push_back({Style::bold_dashed, "", stem + "_stripes_fit.csv", colour, 0, marker, {"im", "p"}});
      // The key: a colour and marker per variant, then a style per series
      // (alike in every panel).
      if (!keyed[v]) panel.lines.push_back({Style::bold, label, "", colour, 0, marker});
      keyed[v] = true;
      banded = banded || f.capacity_bootstrap.computed();
    }
    if (l + 1 == summary.limits().size()) {
      const bool modelling = any_modelling(fragility_of);
      panel.lines.push_back({Style::bold,
                             modelling ? "fit to first levels, beta with modelling" : "fit to first levels",
                             "", -1});
      if (banded) panel.lines.push_back({Style::band, interval_words + " of that fit (bootstrap)", "", -1});
      panel.lines.push_back({Style::circles, "each record's first level at the limit", "", -1});
      panel.lines.push_back({Style::squares, "fraction at each level", "", -1});
      panel.lines.push_back({Style::bold_dashed, "fit to the fractions", "", -1});
    }
    panels.push_back(panel);
  }
  if (!panels.empty() && nr >= 2) {
    const int fc = static_cast<int>(std::min<std::size_t>(panels.size(), 2));
    const int fr = static_cast<int>((panels.size() + 1) / 2);
    plot::Figure fig = figure(kind + "_fragility",
                              fmt::format("{}: fragility over {} records, by limit state\n(first levels: the level "
                                          "at which each record first reaches the limit)",
                                          scene_name, nr));
    fig.width = std::max(1100, 640 * fc + 120);
    fig.height = 560 * fr + 300;
    for (const fs::path& f : plot::render_lines(fig, fr, fc, im_axis_label(im), "P(limit reached | IM) [-]", panels))
      written.push_back(f);
  }
}

// Damage states: every limit's fit and band in one panel per variant, the
// limits told apart by dash and colour.
void LadderReport::damage_states(std::vector<fs::path>& written) const {
  using Style = plot::Line::Style;
  const std::string interval_words = this->interval_words();
  bool banded = this->banded();
  if (summary.limits().size() >= 2 && nr >= 2) {
    std::vector<plot::LinePanel> states;
    for (std::size_t v = 0; v < nv; ++v) {
      plot::LinePanel panel{variant_label(st.variants()[v].name), {}, "0:1.02", fmt::format("0:{:.6g}", top)};
      for (std::size_t l = 0; l < summary.limits().size(); ++l) {
        if (!fragility_of[v][l] || !fragility_of[v][l]->capacity_fit.fitted) continue;
        const LimitFragility& f = *fragility_of[v][l];
        const std::string stem = fmt::format("{}/fragility_{}_{}", data, l, v);
        const std::string title = limit_title(f.limit);
        const int colour = static_cast<int>(l);
        if (f.capacity_bootstrap.computed()) {
          panel.lines.push_back({Style::band, "", stem + "_band.csv", colour, 0, 0, {"im", "low", "high"}});
          banded = true;
        }
        panel.lines.push_back({Style::bold, title, stem + "_fit.csv", colour, static_cast<int>(l), 0, {"im", "p"}});
      }
      if (v + 1 == nv && banded)
        panel.lines.push_back({Style::band, interval_words + " (bootstrap)", "", -1});
      states.push_back(panel);
    }
    const int fc = static_cast<int>(std::min<std::size_t>(states.size(), 2));
    const int fr = static_cast<int>((states.size() + 1) / 2);
    plot::Figure fig = figure(kind + "_damage_states",
                              fmt::format("{}: damage states over {} records\n(lognormal fits to the level at which "
                                          "each record first reaches each limit{})",
                                          scene_name, nr, interval_words.empty() ? "" : "; bands: " + interval_words +
                                                                                             " by bootstrap over records"));
    fig.width = std::max(1100, 640 * fc + 120);
    fig.height = 560 * fr + 300;
    for (const fs::path& f : plot::render_lines(fig, fr, fc, im_axis_label(im), "P(limit reached | IM) [-]", states))
      written.push_back(f);
  }
}

}  // namespace

std::vector<fs::path> draw_ladder_report(const fs::path& dir, const Study& st, const StudySummary& summary,
                                         const SuiteFragility& fragility_of, const std::string& kind, const std::string& scene_name,
                                         const std::vector<std::string>& formats) {
  make_output_dir(dir / (kind + "_suite.data"));
  const LadderReport report{dir, st, summary, fragility_of, kind, scene_name, formats};
  std::vector<fs::path> written;
  report.ida_curves(written);
  report.fragility(written);
  report.damage_states(written);
  return written;
}

}  // namespace rocking::app
