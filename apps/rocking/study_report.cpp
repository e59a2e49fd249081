// Summaries and suite figures of `rocking ida` and `rocking sweep` (MODEL.md
// 13): the numbers come from rocking.study's StudySummary and
// rocking.fragility; this file writes them and draws them.
#include "study_report.hpp"
#include "run_output.hpp"
#include <nlohmann/json.hpp>
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>

namespace rocking::app {

namespace fs = std::filesystem;

namespace {

std::string num(double v) { return std::isinf(v) ? "inf" : fmt::format("{:.6g}", v); }

// Whether a variant can reach a limit at all (a fixed base never overturns).
bool applies(const Study& st, std::size_t variant, const Limit& limit) {
  if (!limit.quantity) return st.can_overturn(variant);
  return st.reports(variant, *limit.quantity);
}

std::string interval(const std::array<double, 2>& i) {
  return std::isnan(i[0]) ? std::string(",") : fmt::format("{},{}", num(i[0]), num(i[1]));
}

std::string fit_row(const std::string& variant, const std::string& limit, const std::string& im, const LognormalFit& f,
                    const FitBootstrap& b, double beta_modelling) {
  const auto total = [&](double beta) { return std::isnan(beta) ? beta : total_beta(beta, beta_modelling); };
  return fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", csv_field(variant), csv_field(limit), im,
                     f.method, f.fitted ? num(f.median) : "", f.fitted ? num(f.beta) : "",
                     f.fitted ? num(f.log_median_se) : "", f.fitted ? num(f.beta_se) : "",
                     f.fitted ? interval(b.median) : ",", f.fitted ? interval(b.beta) : ",",
                     f.fitted ? num(total(f.beta)) : "", f.fitted ? interval({total(b.beta[0]), total(b.beta[1])}) : ",",
                     b.draws, b.fitted, f.records, f.reached, csv_field(f.note));
}

// fragility.csv: each fit with its bootstrap's 90 % intervals (empty when
// not computed), beta_total with modelling dispersion, the resamples drawn
// and fitted.
const char* fragility_header =
    "variant,limit,im,method,median,beta,log_median_se,beta_se,median_low,median_high,beta_low,beta_high,beta_total,"
    "beta_total_low,beta_total_high,bootstrap_draws,bootstrap_fitted,records,reached,note\n";
const char* points_header = "variant,limit,im,source,record,level,fraction,runs,reached\n";

// The capacity points: each record's capacity, the reached ones with their
// empirical probability (rank over every record).
std::string capacity_points(const std::string& variant, const std::string& limit, const std::string& im,
                            std::vector<std::pair<std::size_t, Capacity>> caps, const std::vector<std::string>& ids) {
  std::stable_sort(caps.begin(), caps.end(), [](const auto& a, const auto& b) {
    return a.second.reached != b.second.reached ? a.second.reached : a.second.im < b.second.im;
  });
  std::string out;
  for (std::size_t k = 0; k < caps.size(); ++k) {
    const auto& [r, c] = caps[k];
    out += fmt::format("{},{},{},capacity,{},{},{},1,{}\n", csv_field(variant), csv_field(limit), im, csv_field(ids[r]),
                       num(c.im), c.reached ? num(static_cast<double>(k + 1) / static_cast<double>(caps.size())) : "",
                       c.reached ? 1 : 0);
  }
  return out;
}

void print_fit(const std::string& variant, const std::string& limit, const IntensityMeasure& im, const LognormalFit& f,
               const FitBootstrap& b, double beta_modelling) {
  if (!f.fitted) {
    fmt::print("{}: {}: no {} fit: {}\n", variant, limit, f.method, f.note);
    return;
  }
  const std::string unit = im.unit().empty() ? "" : " " + im.unit();
  const std::string median_ci = b.computed() ? fmt::format(" [{:.3g}, {:.3g}]", b.median[0], b.median[1]) : "";
  const std::string beta_ci = b.computed() ? fmt::format(" [{:.3f}, {:.3f}]", b.beta[0], b.beta[1]) : "";
  const std::string total =
      beta_modelling > 0 ? fmt::format(", beta_total {:.3f} with modelling {:g}", total_beta(f.beta, beta_modelling), beta_modelling)
                         : "";
  fmt::print("{}: {} median {} {:.4g}{}{}, beta {:.3f}{}{} ({}{} of {} {}; {})\n", variant, limit, im.name(), f.median,
             unit, median_ci, f.beta, beta_ci, total,
             b.computed() ? fmt::format("{:g} % intervals by bootstrap; ", b.level * 100) : "", f.reached, f.records,
             f.method == "stripes-mle" ? "runs" : "records", f.method);
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
  const std::string unit(q.scalar ? info(*q.scalar).figure_unit : info(q.of).figure_unit);
  const std::string words =
      q.scalar ? std::string(axis_words(info(*q.scalar).words)) : q.device + " " + std::string(axis_words(info(q.of).words));
  return fmt::format("{} ≥ {:g}{}", words, limit.value * factor, unit == "-" ? "" : " " + unit);
}

}  // namespace

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return out + "\"";
}

std::string im_words(const IntensityMeasure& im) {
  const std::string damping = fmt::format("{:g} %", im.damping * 100);
  switch (im.kind) {
    case IntensityMeasure::Kind::scale_factor: return "the scale factor on the record";
    case IntensityMeasure::Kind::pga: return "PGA";
    case IntensityMeasure::Kind::pgv: return "PGV";
    case IntensityMeasure::Kind::sa: return fmt::format("Sa({:.3g} s), {}", im.t1, damping);
    case IntensityMeasure::Kind::saavg: return fmt::format("Sa,avg({:.3g}-{:.3g} s), {}", im.t1, im.t2, damping);
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
  }
  return im.name();
}

SuiteFragility suite_fragility(const Study& st, const StudySummary& summary, const FragilityOptions& options,
                               int threads) {
  const std::size_t nv = st.variants().size(), nl = summary.limits().size();
  SuiteFragility out(nv, std::vector<std::optional<LimitFragility>>(nl));
  // Each (variant, limit) is one task: its bootstrap is the work.
  const std::function<std::optional<LimitFragility>(std::size_t)> work = [&](std::size_t i) {
    const std::size_t v = i / nl, l = i % nl;
    if (!applies(st, v, summary.limits()[l])) return std::optional<LimitFragility>();
    return std::optional<LimitFragility>(summary.fragility(v, l, options));
  };
  parallel_ordered<std::optional<LimitFragility>>(
      nv * nl, threads, work, [&](std::size_t i, const std::optional<LimitFragility>& f) { out[i / nl][i % nl] = f; });
  return out;
}

void write_ladder_report(const fs::path& dir, const Study& st, const StudySummary& summary,
                         const SuiteFragility& fragility_of, const std::vector<std::string>& ids) {
  const IntensityMeasure& im = st.intensity_measure();
  std::string fractiles = "variant,quantity,im,level,runs,collapsed,p16,p50,p84\n";
  std::string fragility = fragility_header, points = points_header;
  nlohmann::json json{{"im", im.name()},
                      {"unit", im.unit()},
                      {"damping", im.damping},
                      {"levels", summary.levels()},
                      {"resurrection", summary.resurrection() == Resurrection::first ? "first" : "keep"},
                      {"records", ids},
                      {"variants", nlohmann::json::array()}};
  for (std::size_t v = 0; v < st.variants().size(); ++v) {
    const std::string& name = st.variants()[v].name;
    nlohmann::json jv{{"name", name}, {"fractiles", nlohmann::json::object()}, {"fragility", nlohmann::json::array()}};
    for (const QuantityName& q : study_columns(st).all()) {
      // By column: level, runs, collapsed, p16, p50, p84 (null: a collapse,
      // JSON having no infinity).
      nlohmann::json cols{{"level", nlohmann::json::array()}, {"runs", nlohmann::json::array()},
                          {"collapsed", nlohmann::json::array()}, {"p16", nlohmann::json::array()},
                          {"p50", nlohmann::json::array()}, {"p84", nlohmann::json::array()}};
      const char* keys[] = {"p16", "p50", "p84"};
      for (const StudySummary::FractileRow& row : summary.fractiles(v, q)) {
        fractiles += fmt::format("{},{},{},{},{},{},{},{},{}\n", csv_field(name), csv_field(q.name()), im.name(),
                                 num(row.level), row.runs, row.collapsed, num(row.edp[0]), num(row.edp[1]),
                                 num(row.edp[2]));
        cols["level"].push_back(row.level);
        cols["runs"].push_back(row.runs);
        cols["collapsed"].push_back(row.collapsed);
        for (std::size_t i = 0; i < 3; ++i)
          cols[keys[i]].push_back(std::isinf(row.edp[i]) ? nlohmann::json(nullptr) : nlohmann::json(row.edp[i]));
      }
      if (!cols["level"].empty()) jv["fractiles"][q.name()] = std::move(cols);
    }
    for (std::size_t l = 0; l < summary.limits().size(); ++l) {
      if (!fragility_of[v][l]) continue;
      const LimitFragility& f = *fragility_of[v][l];
      const Limit& limit = f.limit;
      fragility += fit_row(name, limit.name, im.name(), f.capacity_fit, f.capacity_bootstrap, f.beta_modelling) +
                   fit_row(name, limit.name, im.name(), f.stripes_fit, f.stripes_bootstrap, f.beta_modelling);
      points += capacity_points(name, limit.name, im.name(), f.capacities, ids);
      for (const Stripe& s : f.stripes)
        points += fmt::format("{},{},{},stripe,,{},{},{},{}\n", csv_field(name), csv_field(limit.name), im.name(),
                              num(s.im), num(static_cast<double>(s.reached) / static_cast<double>(s.runs)), s.runs,
                              s.reached);
      jv["fragility"].push_back(fragility_json(f, ids));
      if (!limit.quantity) {
        print_fit(name, limit.name, im, f.capacity_fit, f.capacity_bootstrap, f.beta_modelling);
        print_fit(name, limit.name, im, f.stripes_fit, f.stripes_bootstrap, f.beta_modelling);
      }
    }
    // Records that stand again above their first overturning.
    nlohmann::json jr = nlohmann::json::array();
    std::size_t levels_survived = 0;
    const auto resurrections = summary.resurrections(v);
    for (const StudySummary::Resurrections& r : resurrections) {
      jr.push_back({{"record", ids[r.record]}, {"first_overturning", r.first_overturning}, {"survived", r.survived}});
      levels_survived += r.survived.size();
    }
    jv["resurrections"] = std::move(jr);
    if (!resurrections.empty())
      fmt::print("{}: {} of {} records survive {} level(s) above their first overturning; {}\n", name,
                 resurrections.size(), ids.size(), levels_survived,
                 summary.resurrection() == Resurrection::first
                     ? "counted as overturned there (--resurrection first)"
                     : "counted as standing there (--resurrection keep)");
    json["variants"].push_back(jv);
  }
  write_text(dir / "summary.csv", fractiles);
  write_text(dir / "fragility.csv", fragility);
  write_text(dir / "fragility_points.csv", points);
  write_text(dir / "summary.json", json.dump(1) + "\n");
  fmt::print("wrote {} (16/50/84 % fractiles), {}, {}, {}\n", (dir / "summary.csv").string(),
             (dir / "fragility.csv").string(), (dir / "fragility_points.csv").string(), (dir / "summary.json").string());
}

std::vector<fs::path> draw_ladder_report(const fs::path& dir, const Study& st, const StudySummary& summary,
                                         const SuiteFragility& fragility_of, const std::string& kind, const std::string& scene_name,
                                         const std::vector<std::string>& formats) {
  using Style = plot::Line::Style;
  const IntensityMeasure& im = st.intensity_measure();
  const std::string data = kind + "_suite.data";
  make_output_dir(dir / data);
  const std::size_t nv = st.variants().size();
  const int cols = static_cast<int>(std::min<std::size_t>(nv, 3));
  const int rows = static_cast<int>((nv + 2) / 3);
  const std::size_t nr = st.records().size();
  std::vector<fs::path> written;
  auto figure = [&](const std::string& name, const std::string& title) {
    plot::Figure fig;
    fig.dir = dir;
    fig.name = name;
    fig.title = title;
    fig.formats = formats;
    fig.width = 560 * cols + 120;
    fig.height = 470 * rows + 200;
    return fig;
  };
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
      panel.lines.push_back({Style::thin_grey, "each record", stem + "_records.csv", 0});
      panel.lines.push_back({Style::crosses, "overturns (x)", stem + "_overturns.csv", 5});
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
                               i == 1 ? 0 : i == 0 ? 1 : 2});
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
  // The fitted CDF (the capacity fit with its total dispersion) and its band
  // at 200 levels up to the top of the axis.
  const double top = summary.levels().empty() ? 1 : summary.levels().back() * 1.1;
  auto fit_curve = [&](const LognormalFit& f, double beta_modelling) {
    std::string text = "im,p\n";
    if (f.fitted)
      for (int k = 1; k <= 200; ++k) {
        const double x = top * k / 200.0;
        text += fmt::format("{:.6g},{:.6g}\n", x, lognormal_cdf(x, f.median, total_beta(f.beta, beta_modelling)));
      }
    return text;
  };
  auto band = [&](const FitBootstrap& b, double beta_modelling) {
    std::string text = "im,low,high\n";
    if (b.computed())
      for (int k = 1; k <= 200; ++k) {
        const double x = top * k / 200.0;
        const auto [low, high] = cdf_band(b, x, beta_modelling);
        text += fmt::format("{:.6g},{:.6g},{:.6g}\n", x, low, high);
      }
    return text;
  };
  const std::string interval_words =
      fragility_of.empty() || fragility_of[0].empty() || !fragility_of[0][0]
          ? std::string()
          : fmt::format("{:g} % interval", fragility_of[0][0]->capacity_bootstrap.level * 100);
  // Fragility: one panel per limit state, one colour per variant.
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
      const int colour = static_cast<int>(v);
      if (f.capacity_bootstrap.computed()) panel.lines.push_back({Style::band, "", stem + "_band.csv", colour});
      panel.lines.push_back({Style::bold, "", stem + "_fit.csv", colour});
      panel.lines.push_back({Style::circles, "", stem + "_records.csv", colour});
      panel.lines.push_back({Style::squares, "", stem + "_stripes.csv", colour});
      panel.lines.push_back({Style::bold_dashed, "", stem + "_stripes_fit.csv", colour});
      // The key: a colour per variant, then a style per series (alike in every panel).
      if (!keyed[v]) panel.lines.push_back({Style::bold, label, "", colour});
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
  // Damage states: every limit's fit and band in one panel per variant, the
  // limits told apart by dash and colour.
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
          panel.lines.push_back({Style::band, "", stem + "_band.csv", colour});
          banded = true;
        }
        panel.lines.push_back({Style::bold, title, stem + "_fit.csv", colour, static_cast<int>(l)});
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
  return written;
}

void write_hunt_report(const fs::path& dir, const Study& st, const std::vector<HuntResult>& hunts,
                       const std::vector<std::string>& ids, const FragilityOptions& options) {
  const IntensityMeasure& im = st.intensity_measure();
  const std::size_t nv = st.variants().size();
  std::string fragility = fragility_header, points = points_header;
  nlohmann::json json{{"im", im.name()}, {"unit", im.unit()}, {"damping", im.damping}, {"records", ids},
                      {"variants", nlohmann::json::array()}};
  for (std::size_t v = 0; v < nv; ++v) {
    const std::string& name = st.variants()[v].name;
    if (!st.can_overturn(v)) continue;
    const auto caps = hunt_capacities(hunts, nv, v);
    nlohmann::json jr = nlohmann::json::array();
    for (const auto& [r, capacity] : caps) {
      const HuntResult& h = hunts[r * nv + v];
      if (!h.resurrections.empty()) {
        nlohmann::json ranges = nlohmann::json::array();
        for (const auto& [from, to] : h.resurrections) ranges.push_back({from, to});
        jr.push_back({{"record", ids[r]}, {"first_overturning", h.collapse_level}, {"survived", ranges}});
      }
    }
    const LimitFragility f = capacity_fragility(overturning_limit(), caps, options);
    fragility += fit_row(name, "overturning", im.name(), f.capacity_fit, f.capacity_bootstrap, f.beta_modelling);
    points += capacity_points(name, "overturning", im.name(), caps, ids);
    json["variants"].push_back({{"name", name}, {"fragility", {fragility_json(f, ids)}}, {"resurrections", jr}});
    if (st.records().size() >= 2)
      print_fit(name, "overturning", im, f.capacity_fit, f.capacity_bootstrap, f.beta_modelling);
  }
  write_text(dir / "fragility.csv", fragility);
  write_text(dir / "fragility_points.csv", points);
  write_text(dir / "summary.json", json.dump(1) + "\n");
}

}  // namespace rocking::app
