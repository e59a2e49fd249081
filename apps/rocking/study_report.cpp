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

nlohmann::json fit_json(const LognormalFit& f) {
  nlohmann::json j{{"method", f.method}, {"fitted", f.fitted}, {"records", f.records}, {"reached", f.reached},
                   {"note", f.note}};
  if (f.fitted) {
    j["median"] = f.median;
    j["beta"] = f.beta;
    j["log_median_se"] = f.log_median_se;
    j["beta_se"] = f.beta_se;
  }
  return j;
}

std::string fit_row(const std::string& variant, const std::string& limit, const std::string& im, const LognormalFit& f) {
  return fmt::format("{},{},{},{},{},{},{},{},{},{},{}\n", csv_field(variant), csv_field(limit), im, f.method,
                     f.fitted ? num(f.median) : "", f.fitted ? num(f.beta) : "", f.fitted ? num(f.log_median_se) : "",
                     f.fitted ? num(f.beta_se) : "", f.records, f.reached, csv_field(f.note));
}

const char* fragility_header = "variant,limit,im,method,median,beta,log_median_se,beta_se,records,reached,note\n";
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

void print_fit(const std::string& variant, const std::string& limit, const IntensityMeasure& im, const LognormalFit& f) {
  if (f.fitted)
    fmt::print("{}: {} median {} {:.4g}{} (beta {:.3f}; {} of {} {}; {})\n", variant, limit, im.name(), f.median,
               im.unit().empty() ? "" : " " + im.unit(), f.beta, f.reached, f.records,
               f.method == "stripes-mle" ? "runs" : "records", f.method);
  else
    fmt::print("{}: {}: no {} fit: {}\n", variant, limit, f.method, f.note);
}

}  // namespace

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return out + "\"";
}

std::string im_axis_label(const IntensityMeasure& im) {
  const std::string damping = im.damping == 0.05 ? "" : fmt::format(", {:g} %", im.damping * 100);
  switch (im.kind) {
    case IntensityMeasure::Kind::scale_factor: return "scale factor on the record [-]";
    case IntensityMeasure::Kind::pga: return "PGA [g]";
    case IntensityMeasure::Kind::pgv: return "PGV [m/s]";
    case IntensityMeasure::Kind::sa: return fmt::format("S_a({:.4g} s{}) [g]", im.t1, damping);
    case IntensityMeasure::Kind::saavg: return fmt::format("S_{{a,avg}}({:.4g}-{:.4g} s{}) [g]", im.t1, im.t2, damping);
  }
  return im.name();
}

void write_ladder_report(const fs::path& dir, const Study& st, const StudySummary& summary,
                         const std::vector<std::string>& ids) {
  const IntensityMeasure& im = st.intensity_measure();
  std::string fractiles = "variant,quantity,im,level,runs,collapsed,p16,p50,p84\n";
  std::string fragility = fragility_header, points = points_header;
  nlohmann::json json{{"im", im.name()}, {"unit", im.unit()}, {"damping", im.damping}, {"levels", summary.levels()},
                      {"records", ids}, {"variants", nlohmann::json::array()}};
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
      const Limit& limit = summary.limits()[l];
      if (!applies(st, v, limit)) continue;
      const auto caps = summary.capacities(v, l);
      std::vector<Capacity> values;
      for (const auto& c : caps) values.push_back(c.second);
      const std::vector<Stripe> stripes = summary.stripes(v, l);
      const LognormalFit by_capacity = fit_capacities(values), by_stripes = fit_stripes(stripes);
      fragility += fit_row(name, limit.name, im.name(), by_capacity) + fit_row(name, limit.name, im.name(), by_stripes);
      points += capacity_points(name, limit.name, im.name(), caps, ids);
      nlohmann::json jc = nlohmann::json::array(), js = nlohmann::json::array();
      for (const auto& [r, c] : caps) jc.push_back({{"record", ids[r]}, {"level", c.im}, {"reached", c.reached}});
      for (const Stripe& s : stripes) {
        points += fmt::format("{},{},{},stripe,,{},{},{},{}\n", csv_field(name), csv_field(limit.name), im.name(),
                              num(s.im), num(static_cast<double>(s.reached) / static_cast<double>(s.runs)), s.runs,
                              s.reached);
        js.push_back({{"level", s.im}, {"runs", s.runs}, {"reached", s.reached}});
      }
      jv["fragility"].push_back({{"limit", limit.name}, {"capacity_fit", fit_json(by_capacity)},
                                 {"stripes_fit", fit_json(by_stripes)}, {"capacities", jc}, {"stripes", js}});
      if (!limit.quantity) {
        print_fit(name, limit.name, im, by_capacity);
        print_fit(name, limit.name, im, by_stripes);
      }
    }
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
                                         const std::string& kind, const std::string& scene_name,
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
        panel.lines.push_back({i == 1 ? Style::bold : Style::bold_dashed,
                               i == 1 ? "50 % fractile" : "16 % and 84 % fractiles", file, i == 1 ? 0 : 1});
      }
      panels.push_back(panel);
    }
    const plot::Figure fig = figure(
        fmt::format("{}_{}", kind, q),
        fmt::format("{}: IDA curves over {} records, by {}\n(thin: each record; bold: fractiles, flat where they "
                    "overturn)",
                    scene_name, nr, im.name()));
    for (const fs::path& f : plot::render_lines(fig, rows, cols, "peak " + axis_label(axis_q), im_axis_label(im), panels)) written.push_back(f);
  }
  // Fragility: one panel per limit state, one colour per variant.
  std::vector<plot::LinePanel> panels;
  const double top = summary.levels().empty() ? 1 : summary.levels().back() * 1.1;
  for (std::size_t l = 0; l < summary.limits().size(); ++l) {
    const Limit& limit = summary.limits()[l];
    plot::LinePanel panel{limit.name == "overturning" ? std::string("overturning") : limit.name, {}, "0:1.02",
                          fmt::format("0:{:.6g}", top)};
    for (std::size_t v = 0; v < nv; ++v) {
      if (!applies(st, v, limit)) continue;
      const std::string label = variant_label(st.variants()[v].name);
      const std::string stem = fmt::format("{}/fragility_{}_{}", data, l, v);
      const auto caps = summary.capacities(v, l);
      std::vector<Capacity> values;
      for (const auto& c : caps) values.push_back(c.second);
      const LognormalFit fit = fit_capacities(values);
      const std::vector<Stripe> stripes = summary.stripes(v, l);
      std::vector<double> reached;
      for (const Capacity& c : values)
        if (c.reached) reached.push_back(c.im);
      std::sort(reached.begin(), reached.end());
      // The fitted CDF at 200 levels up to the top of the axis.
      auto fit_curve = [&](const LognormalFit& f) {
        std::string text = "im,p\n";
        if (f.fitted)
          for (int k = 1; k <= 200; ++k) {
            const double x = top * k / 200.0;
            text += fmt::format("{:.6g},{:.6g}\n", x, lognormal_cdf(x, f.median, f.beta));
          }
        return text;
      };
      std::string ecdf = "im,p\n", stripe_text = "im,p\n";
      for (std::size_t k = 0; k < reached.size(); ++k)
        ecdf += fmt::format("{:.6g},{:.6g}\n", reached[k], static_cast<double>(k + 1) / static_cast<double>(values.size()));
      for (const Stripe& s : stripes)
        stripe_text += fmt::format("{:.6g},{:.6g}\n", s.im, static_cast<double>(s.reached) / static_cast<double>(s.runs));
      write_text(dir / (stem + "_records.csv"), ecdf);
      write_text(dir / (stem + "_stripes.csv"), stripe_text);
      write_text(dir / (stem + "_fit.csv"), fit_curve(fit));
      const int colour = static_cast<int>(v);
      panel.lines.push_back({Style::bold, label + ": fit to the records", stem + "_fit.csv", colour});
      panel.lines.push_back({Style::circles, label + ": each record", stem + "_records.csv", colour});
      panel.lines.push_back({Style::squares, label + ": fraction at each level", stem + "_stripes.csv", colour});
      write_text(dir / (stem + "_stripes_fit.csv"), fit_curve(fit_stripes(stripes)));
      panel.lines.push_back({Style::bold_dashed, label + ": fit to the fractions", stem + "_stripes_fit.csv", colour});
    }
    panels.push_back(panel);
  }
  if (!panels.empty() && nr >= 2) {
    const int fc = static_cast<int>(std::min<std::size_t>(panels.size(), 2));
    const int fr = static_cast<int>((panels.size() + 1) / 2);
    plot::Figure fig = figure(kind + "_fragility",
                              fmt::format("{}: fragility over {} records\n(circles: the level at which each record "
                                          "first reaches the limit; squares: the fraction at each level)",
                                          scene_name, nr));
    fig.width = std::max(1100, 640 * fc + 120);
    fig.height = 560 * fr + 300;
    for (const fs::path& f : plot::render_lines(fig, fr, fc, im_axis_label(im), "P(limit reached | IM) [-]", panels))
      written.push_back(f);
  }
  return written;
}

void write_hunt_report(const fs::path& dir, const Study& st, const std::vector<HuntResult>& hunts,
                       const std::vector<std::string>& ids) {
  const IntensityMeasure& im = st.intensity_measure();
  const std::size_t nv = st.variants().size();
  std::string fragility = fragility_header, points = points_header;
  nlohmann::json json{{"im", im.name()}, {"unit", im.unit()}, {"damping", im.damping}, {"records", ids},
                      {"variants", nlohmann::json::array()}};
  for (std::size_t v = 0; v < nv; ++v) {
    const std::string& name = st.variants()[v].name;
    if (!st.can_overturn(v)) continue;
    std::vector<std::pair<std::size_t, Capacity>> caps;
    std::vector<Capacity> values;
    nlohmann::json jc = nlohmann::json::array();
    for (std::size_t r = 0; r < st.records().size(); ++r) {
      const HuntResult& h = hunts[r * nv + v];
      if (!h.error.empty() || h.runs == 0) continue;
      caps.emplace_back(r, hunt_capacity(h));
      values.push_back(caps.back().second);
      jc.push_back({{"record", ids[r]}, {"level", values.back().im}, {"reached", values.back().reached}});
    }
    const LognormalFit fit = fit_capacities(values);
    fragility += fit_row(name, "overturning", im.name(), fit);
    points += capacity_points(name, "overturning", im.name(), caps, ids);
    json["variants"].push_back({{"name", name}, {"fragility", {{{"limit", "overturning"}, {"capacity_fit", fit_json(fit)},
                                                                {"capacities", jc}}}}});
    if (st.records().size() >= 2) print_fit(name, "overturning", im, fit);
  }
  write_text(dir / "fragility.csv", fragility);
  write_text(dir / "fragility_points.csv", points);
  write_text(dir / "summary.json", json.dump(1) + "\n");
}

}  // namespace rocking::app
