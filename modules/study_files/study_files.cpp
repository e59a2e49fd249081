module;
#include <nlohmann/json.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <istream>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>
module rocking.study_files;
import rocking.errors;

namespace rocking {

namespace fs = std::filesystem;

namespace {

std::string num(double v) { return std::isinf(v) ? "inf" : fmt::format("{:.6g}", v); }

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
// empirical probability (rank over every record). Reached first, by level;
// equal levels in record order.
std::string capacity_points(const std::string& variant, const std::string& limit, const std::string& im,
                            std::vector<std::pair<std::size_t, Capacity>> caps, const std::vector<std::string>& ids) {
  std::sort(caps.begin(), caps.end(), [](const auto& a, const auto& b) {
    if (a.second.reached != b.second.reached) return a.second.reached;
    return a.second.im != b.second.im ? a.second.im < b.second.im : a.first < b.first;
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

// A fit in one line for the user.
std::string fit_note(const std::string& variant, const std::string& limit, const IntensityMeasure& im,
                     const LognormalFit& f, const FitBootstrap& b, double beta_modelling) {
  if (!f.fitted) return fmt::format("{}: {}: no {} fit: {}", variant, limit, f.method, f.note);
  const std::string unit = im.unit().empty() ? "" : " " + im.unit();
  const std::string median_ci = b.computed() ? fmt::format(" [{:.3g}, {:.3g}]", b.median[0], b.median[1]) : "";
  const std::string beta_ci = b.computed() ? fmt::format(" [{:.3f}, {:.3f}]", b.beta[0], b.beta[1]) : "";
  const std::string total =
      beta_modelling > 0 ? fmt::format(", beta_total {:.3f} with modelling {:g}", total_beta(f.beta, beta_modelling), beta_modelling)
                         : "";
  return fmt::format("{}: {} median {} {:.4g}{}{}, beta {:.3f}{}{} ({}{} of {} {}; {})", variant, limit, im.name(),
                     f.median, unit, median_ci, f.beta, beta_ci, total,
                     b.computed() ? fmt::format("{:g} % intervals by bootstrap; ", b.level * 100) : "", f.reached,
                     f.records, f.method == "stripes-mle" ? "runs" : "records", f.method);
}

}  // namespace

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return out + "\"";
}

std::string exact_number(double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string(); }

std::string peak_field(double v) { return std::isnan(v) ? std::string() : fmt::format("{:.9g}", v); }

std::vector<std::string> record_ids(const std::vector<std::string>& paths) {
  const std::size_t n = paths.size();
  std::vector<std::vector<std::string>> parts(n);
  for (std::size_t i = 0; i < n; ++i)
    for (const fs::path& p : fs::path(paths[i]).lexically_normal()) parts[i].insert(parts[i].begin(), p.string());
  std::vector<std::size_t> depth(n, 1);
  auto id = [&](std::size_t i) {
    std::string out;
    for (std::size_t k = std::min(depth[i], parts[i].size()); k-- > 0;) out += (out.empty() ? "" : "/") + parts[i][k];
    return out;
  };
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<std::size_t> deeper;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j)
        if (i != j && id(i) == id(j) && depth[i] < parts[i].size() && parts[i] != parts[j]) {
          deeper.push_back(i);
          break;
        }
    for (std::size_t i : deeper) ++depth[i];
    changed = !deeper.empty();
  }
  std::vector<std::string> ids(n);
  for (std::size_t i = 0; i < n; ++i) {
    ids[i] = id(i);
    const auto same = std::count_if(ids.begin(), ids.begin() + static_cast<long>(i), [&](const std::string& s) {
      return s == ids[i] || s.starts_with(ids[i] + "#");
    });
    if (same > 0) ids[i] += fmt::format("#{}", same + 1);
  }
  return ids;
}

std::string study_csv_header(const StudyColumns& columns) {
  // No quantity columns (no variant could be built: every run fails) leave
  // none in the header either, as in the rows.
  const auto names = columns.names();
  return fmt::format("record,scale,variant,im,level,record_im,{}top_total_mm,outcome,uplifts,impacts,rhs,error\n",
                     names.empty() ? std::string() : fmt::format("{},", fmt::join(names, ",")));
}

std::string job_fields(const Study& st, const std::vector<std::string>& ids, const Job& job) {
  return fmt::format("{},{},{},{},{},{}", csv_field(ids[job.record]), exact_number(job.scale),
                     csv_field(st.variants()[job.variant].name), st.intensity_measure().name(),
                     exact_number(job.level), exact_number(st.record_intensity(job.record)));
}

std::string study_csv_row(const Study& st, const StudyColumns& columns, const std::vector<std::string>& ids,
                          const Job& job, const JobResult& r) {
  std::string q;
  const RunResult& run = r.run;
  const StudyRow row = study_row(columns, job, r);
  if (row.ran)
    for (double v : row.values) q += peak_field(v) + ",";
  else
    q.assign(columns.size(), ',');
  return fmt::format("{},{}{},{},{},{},{}\n", job_fields(st, ids, job), q,
                     r.error.empty() ? fmt::format("{:.6g}", run.top_total_mm) : "", outcome_name(run.outcome),
                     run.counts.uplifts, fmt::format("{},{}", run.counts.impacts, run.stats.rhs), csv_field(r.error));
}

namespace {

// A study CSV's fields by the names of its header's columns.
struct StudyCsvFields {
  std::vector<std::string> names;
  std::size_t at(std::string_view name) const {
    return static_cast<std::size_t>(std::ranges::find(names, name) - names.begin());
  }
};

// A field that is a number, whole (strtod reads all of it); none otherwise.
std::optional<double> number_field(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) return std::nullopt;
  return v;
}

// The first field from `first` to `last` (by name, in the header's order)
// that is not empty and not a finite number; none when all are.
std::optional<std::size_t> not_finite(const StudyCsvFields& header, const std::vector<std::string>& f,
                                      std::string_view first, std::string_view last) {
  for (std::size_t c = header.at(first); c <= header.at(last); ++c) {
    const std::optional<double> v = number_field(f[c]);
    if (!f[c].empty() && !(v && std::isfinite(*v))) return c;
  }
  return std::nullopt;
}

StudyRow row_of(const StudyColumns& columns, const StudyCsvFields& header, const std::vector<std::string>& f,
                double level) {
  StudyRow row;
  row.level = level;
  row.ran = f[header.at("error")].empty();
  if (const std::optional<Outcome> o = outcome_named(f[header.at("outcome")])) row.outcome = *o;
  if (!row.ran) return row;
  for (const std::string& name : columns.names()) {
    const std::string& text = f[header.at(name)];
    const std::optional<double> v = number_field(text);
    if (!text.empty() && !v) throw InputError(fmt::format("{}: '{}' is not a number", name, text));
    row.values.push_back(v.value_or(std::nan("")));
  }
  return row;
}

}  // namespace

StudyRow written_row(const StudyColumns& columns, const Job& job, const JobResult& r) {
  StudyRow row = study_row(columns, job, r);
  for (double& v : row.values)
    if (!std::isnan(v)) v = std::stod(peak_field(v));
  return row;
}

StudyRow read_study_row(const StudyColumns& columns, const std::string& row) {
  const std::string header = study_csv_header(columns);
  const StudyCsvFields names{csv_fields(header.substr(0, header.size() - 1))};
  const std::vector<std::string> f = csv_fields(row.ends_with("\n") ? row.substr(0, row.size() - 1) : row);
  if (f.size() < names.names.size())
    throw InputError(fmt::format("a study row of {} fields: expected {}", f.size(), names.names.size()));
  const std::optional<double> level = number_field(f[names.at("level")]);
  if (!level) throw InputError(fmt::format("level: '{}' is not a number", f[names.at("level")]));
  return row_of(columns, names, f, *level);
}

ResumedRows read_resumed_rows(std::istream& in, const std::string& name, const std::vector<Job>& jobs,
                              const std::vector<std::string>& ids, const Study& st, const StudyColumns& columns) {
  ResumedRows r;
  std::string line;
  if (!std::getline(in, line) || line + "\n" != study_csv_header(columns))
    throw InputError(fmt::format("--resume: {}:1: not a study CSV of this version (header differs)", name));
  const StudyCsvFields header{csv_fields(line)};
  for (int n = 2; std::getline(in, line); ++n) {
    if (in.eof()) break;  // a last line without its newline was cut: run that job again
    const std::size_t k = r.rows.size();
    const std::vector<std::string> f = csv_fields(line);
    const std::string expected = k < jobs.size() ? job_fields(st, ids, jobs[k]) : std::string("(no more jobs)");
    if (k >= jobs.size() || f.size() < header.names.size() || !line.starts_with(expected + ","))
      throw InputError(fmt::format("--resume: {}:{}: this row is not job {} of this study ({}): give the same scene, "
                                   "--record, --im, --levels and --variants as the interrupted run",
                                   name, n, k + 1, expected));
    // A kept row holds finite numbers from its level to top_total_mm: one
    // with nan, inf or text (a run gone wrong, or an edited file) runs
    // again, with every job after it.
    if (const std::optional<std::size_t> c = not_finite(header, f, "level", "top_total_mm")) {
      r.rerun = fmt::format("--resume: {}:{}: '{}' in column {}: job {} runs again, with the {} after it", name, n,
                            f[*c], *c + 1, k + 1, jobs.size() - k - 1);
      return r;
    }
    r.rows.push_back(line + "\n");
    r.results.push_back(row_of(columns, header, f, jobs[k].level));
  }
  return r;
}

std::vector<std::string> csv_fields(const std::string& row) {
  std::vector<std::string> out;
  std::size_t from = 0;
  for (std::size_t comma; (comma = row.find(',', from)) != std::string::npos; from = comma + 1)
    out.push_back(row.substr(from, comma - from));
  if (from < row.size() || row.ends_with(",")) out.push_back(row.substr(from));
  return out;
}

std::string records_csv(const Study& st, const std::vector<std::string>& ids) {
  std::string out = "record,file,format,event,date,station,component,pga_g,processing\n";
  for (std::size_t r = 0; r < ids.size(); ++r) {
    const GroundMotion* m = st.motion(r);
    const RecordInfo info = m ? m->info() : RecordInfo{};
    out += fmt::format("{},{},{},{},{},{},{},{},{}\n", csv_field(ids[r]), csv_field(st.records()[r]),
                       csv_field(info.format), csv_field(info.event), csv_field(info.date), csv_field(info.station),
                       csv_field(info.component), m ? fmt::format("{:.6g}", m->peak() / gravity) : std::string(),
                       csv_field(info.processing));
  }
  return out;
}

const std::string hunt_csv_header =
    "record,variant,im,collapse_level,survived_level,collapse_scale,record_im,traced_level,fill_step,precision,"
    "resurrections,runs,error\n";
const std::string hunt_points_header = "record,variant,im,level,why,overturned\n";

std::string hunt_fields(const std::string& record, const std::string& variant, const IntensityMeasure& im) {
  return fmt::format("{},{},{},", csv_field(record), csv_field(variant), im.name());
}

std::string ranges_text(const std::vector<std::pair<double, double>>& ranges) {
  std::string out;
  for (const auto& [from, to] : ranges)
    out += (out.empty() ? "" : " ") + (from == to ? fmt::format("{:.6g}", from) : fmt::format("{:.6g}-{:.6g}", from, to));
  return out;
}

nlohmann::json hunt_json(const HuntResult& h, const std::string& record, const std::string& variant,
                         const IntensityMeasure& im, const HuntOptions& o) {
  const auto maybe = [](bool has, double v) { return has ? nlohmann::json(v) : nlohmann::json(nullptr); };
  nlohmann::json ranges = nlohmann::json::array();
  for (const auto& [from, to] : h.resurrections) ranges.push_back({from, to});
  const std::string error = h.fixed_base ? "fixed base: cannot overturn" : h.error;
  return {{"record", record},
          {"variant", variant},
          {"im", im.name()},
          {"collapse_level", maybe(h.collapsed, h.collapse_level)},
          {"survived_level", h.survived_level},
          {"collapse_scale", maybe(h.collapsed, h.collapse_level / h.record_im)},
          {"record_im", h.record_im},
          {"traced_level", maybe(h.collapsed, h.traced_level)},
          {"fill_step", o.fill_step},
          {"precision", o.precision},
          {"resurrections", std::move(ranges)},
          {"runs", h.runs},
          {"error", error.empty() ? nlohmann::json(nullptr) : nlohmann::json(error)}};
}

std::string hunt_csv_row(const HuntResult& h, const std::string& record, const std::string& variant,
                         const IntensityMeasure& im, const HuntOptions& o) {
  const nlohmann::json values = hunt_json(h, record, variant, im, o);
  std::string out;
  for (const std::string& name : csv_fields(hunt_csv_header.substr(0, hunt_csv_header.size() - 1))) {
    const nlohmann::json& v = values.at(name);
    if (!out.empty()) out += ',';
    if (v.is_string()) out += csv_field(v.get<std::string>());
    else if (v.is_number_integer()) out += std::to_string(v.get<long long>());
    else if (v.is_number()) out += exact_number(v.get<double>());
    else if (v.is_array()) out += ranges_text(v.get<std::vector<std::pair<double, double>>>());
  }
  return out + "\n";
}

std::string hunt_points_rows(const HuntResult& h, const std::string& record, const std::string& variant,
                             const IntensityMeasure& im) {
  std::string out;
  for (const HuntPoint& p : h.points)
    out += hunt_fields(record, variant, im) + fmt::format("{:.9g},{},{}\n", p.level, hunt_reason(p.why), p.overturned ? 1 : 0);
  return out;
}

bool limit_applies(const Study& st, std::size_t variant, const Limit& limit) {
  if (!limit.quantity) return st.can_overturn(variant);
  return st.reports(variant, *limit.quantity);
}

SuiteFragility suite_fragility(const Study& st, const StudySummary& summary, const FragilityOptions& options,
                               int threads) {
  const std::size_t nv = st.variants().size(), nl = summary.limits().size();
  SuiteFragility out(nv, std::vector<std::optional<LimitFragility>>(nl));
  // Each (variant, limit) is one task: its bootstrap is the work.
  const std::function<std::optional<LimitFragility>(std::size_t)> work = [&](std::size_t i) {
    const std::size_t v = i / nl, l = i % nl;
    if (!limit_applies(st, v, summary.limits()[l])) return std::optional<LimitFragility>();
    return std::optional<LimitFragility>(summary.fragility(v, l, options));
  };
  parallel_ordered<std::optional<LimitFragility>>(
      nv * nl, threads, work, [&](std::size_t i, const std::optional<LimitFragility>& f) { out[i / nl][i % nl] = f; });
  return out;
}

StudyReport ladder_report(const Study& st, const StudySummary& summary, const SuiteFragility& fragility_of,
                          const std::vector<std::string>& ids) {
  const IntensityMeasure& im = st.intensity_measure();
  StudyReport out;
  out.summary_csv = "variant,quantity,im,level,runs,collapsed,p16,p50,p84\n";
  out.fragility_csv = fragility_header;
  out.fragility_points_csv = points_header;
  nlohmann::json& json = out.summary;
  json = {{"im", im.name()},
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
        out.summary_csv += fmt::format("{},{},{},{},{},{},{},{},{}\n", csv_field(name), csv_field(q.name()), im.name(),
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
      out.fragility_csv += fit_row(name, limit.name, im.name(), f.capacity_fit, f.capacity_bootstrap, f.beta_modelling) +
                           fit_row(name, limit.name, im.name(), f.stripes_fit, f.stripes_bootstrap, f.beta_modelling);
      out.fragility_points_csv += capacity_points(name, limit.name, im.name(), f.capacities, ids);
      for (const Stripe& s : f.stripes)
        out.fragility_points_csv += fmt::format("{},{},{},stripe,,{},{},{},{}\n", csv_field(name), csv_field(limit.name),
                                                im.name(), num(s.im),
                                                num(static_cast<double>(s.reached) / static_cast<double>(s.runs)),
                                                s.runs, s.reached);
      jv["fragility"].push_back(fragility_json(f, ids));
      if (!limit.quantity) {
        out.notes.push_back(fit_note(name, limit.name, im, f.capacity_fit, f.capacity_bootstrap, f.beta_modelling));
        out.notes.push_back(fit_note(name, limit.name, im, f.stripes_fit, f.stripes_bootstrap, f.beta_modelling));
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
      out.notes.push_back(fmt::format("{}: {} of {} records survive {} level(s) above their first overturning; {}", name,
                                      resurrections.size(), ids.size(), levels_survived,
                                      summary.resurrection() == Resurrection::first
                                          ? "counted as overturned there (--resurrection first)"
                                          : "counted as standing there (--resurrection keep)"));
    json["variants"].push_back(jv);
  }
  return out;
}

StudyReport hunt_report(const Study& st, const std::vector<HuntResult>& hunts, const std::vector<std::string>& ids,
                        const FragilityOptions& options) {
  const IntensityMeasure& im = st.intensity_measure();
  const std::size_t nv = st.variants().size();
  StudyReport out;
  out.fragility_csv = fragility_header;
  out.fragility_points_csv = points_header;
  out.summary = {{"im", im.name()}, {"unit", im.unit()}, {"damping", im.damping}, {"records", ids},
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
    out.fragility_csv += fit_row(name, "overturning", im.name(), f.capacity_fit, f.capacity_bootstrap, f.beta_modelling);
    out.fragility_points_csv += capacity_points(name, "overturning", im.name(), caps, ids);
    out.summary["variants"].push_back({{"name", name}, {"fragility", {fragility_json(f, ids)}}, {"resurrections", jr}});
    if (st.records().size() >= 2)
      out.notes.push_back(fit_note(name, "overturning", im, f.capacity_fit, f.capacity_bootstrap, f.beta_modelling));
  }
  return out;
}

std::vector<fs::path> write_report(const fs::path& dir, const StudyReport& report) {
  std::vector<fs::path> written;
  auto write = [&](const char* name, const std::string& text) {
    write_text(dir / name, text);
    written.push_back(dir / name);
  };
  if (!report.summary_csv.empty()) write("summary.csv", report.summary_csv);
  write("fragility.csv", report.fragility_csv);
  write("fragility_points.csv", report.fragility_points_csv);
  write("summary.json", report.summary.dump(1) + "\n");
  return written;
}

void write_text(const fs::path& file, const std::string& text) {
  const fs::path tmp = file.string() + ".tmp";
  std::FILE* out = std::fopen(tmp.c_str(), "w");
  int error = out == nullptr ? errno : 0;
  if (out != nullptr) {
    if (std::fwrite(text.data(), 1, text.size(), out) != text.size() || std::fflush(out) != 0) error = errno;
    if (std::fclose(out) != 0 && error == 0) error = errno;
  }
  std::error_code ec;
  // The file a previous run left goes first: ext4 writes a file out to disk
  // before a rename may replace another (its auto_da_alloc), which made a
  // short run wait for the disk. Outputs are remade by running again.
  if (error == 0) fs::remove(file, ec);
  if (error == 0) fs::rename(tmp, file, ec);
  if (error != 0 || ec) {
    const std::string why = error != 0 ? std::strerror(error) : ec.message();
    fs::remove(tmp, ec);
    throw RunError(fmt::format("{}: cannot write: {}", file.string(), why));
  }
}

}  // namespace rocking
