#include "run_output.hpp"
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <cerrno>
#include <system_error>
#include <cmath>
#include <cstring>
#include <algorithm>
#include <fstream>
#include <thread>
#include <unistd.h>

namespace rocking::app {

HistoryCsv::HistoryCsv(const std::filesystem::path& file, const GroundMotion& motion, const std::vector<Device>& devices)
    : path_(file.string()), motion_(motion), devices_(devices.size()) {
  file_ = std::fopen(path_.c_str(), "w");
  if (file_ == nullptr) throw InputError(fmt::format("{}: cannot write: {}", path_, std::strerror(errno)));
  std::fputs("t [s],phase,u_N [m],theta [rad],theta/alpha_cg [-],delta_t [-],delta_e [-],d [m],F_hd [N],"
             "base_shear [V_ref],base_moment [M_ref],mid_shear [V_ref],mid_moment [M_ref],a_g [m/s2]", file_);
  if (!devices.empty()) std::fputs(",M_dev [N m]", file_);
  for (const Device& d : devices) fmt::print(file_, ",{0} e [m],{0} F [N]", d.name);
  std::fputs("\n", file_);
}

HistoryCsv::~HistoryCsv() {
  if (file_ != nullptr) std::fclose(file_);
}

void HistoryCsv::record(const Response& r) {
  // A full disk ends the run (RunError, exit 3) naming the file; the rows
  // written before stay.
  if (std::ferror(file_) != 0) throw RunError(fmt::format("{}: cannot write: {}", path_, std::strerror(errno)));
  try {
    print_row(r);
  } catch (const std::system_error& e) {
    throw RunError(fmt::format("{}: cannot write: {}", path_, e.code().message()));
  }
}

void HistoryCsv::print_row(const Response& r) {
  using Q = Quantity;
  fmt::print(file_, "{:.9g},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}", r.t,
             r.pivot == 0 ? "contact" : r.pivot > 0 ? "rock+" : "rock-", r.u_top, r[Q::theta], r[Q::theta_over_alpha],
             r[Q::delta_t], r[Q::delta_e], r[Q::damper_d], r[Q::damper_F], r[Q::base_shear], r[Q::base_moment],
             r[Q::mid_shear], r[Q::mid_moment], motion_.acceleration(r.t));
  if (!devices_.empty()) {
    double moment = 0;
    for (const DeviceSample& d : devices_) moment += d.moment;
    fmt::print(file_, ",{:.9g}", moment);
    for (const DeviceSample& d : devices_) fmt::print(file_, ",{:.9g},{:.9g}", d.e, d.F);
  }
  std::fputs("\n", file_);
}

void HistoryCsv::close() {
  if (file_ == nullptr) return;
  const bool bad = std::ferror(file_) != 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (bad || !closed) throw RunError(fmt::format("{}: cannot write: {}", path_, std::strerror(errno)));
}

void make_output_dir(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw InputError(fmt::format("{}: cannot create the output folder: {}", dir.string(),
                                 ec ? ec.message() : "not a folder"));
}

nlohmann::json summary_json(const RunLabel& label, const RunResult& r) {
  using nlohmann::json;
  json peaks = json::object();
  for (std::size_t i = 0; i < quantity_count; ++i) {
    const auto q = static_cast<Quantity>(i);
    const bool absent = (is_force(q) && !r.has_forces) ||
                        ((q == Quantity::damper_d || q == Quantity::damper_F) && !r.has_damper);
    peaks[std::string(quantity_name(q))] = absent ? json(nullptr) : json(r.peaks[i]);
  }
  auto finite_or_null = [](double t) { return std::isfinite(t) ? json(t) : json(nullptr); };
  json out = {
      {"scene", label.scene},
      {"scene_source", label.scene_source},
      {"motion", label.motion},
      {"record", label.record.empty() ? json(nullptr) : json(label.record)},
      {"scale", label.scale},
      {"scale_factors", {{"scene", label.scene_scale}, {"option", label.option_scale}}},
      {"integrator", r.integrator},
      {"rtol", label.rtol},
      {"atol", label.atol},
      {"peaks", peaks},
      {"top_total_mm", r.top_total_mm},
      {"counts", {{"uplifts", r.counts.uplifts}, {"impacts", r.counts.impacts}}},
      {"first_uplift_s", finite_or_null(r.first_uplift)},
      {"first_impact_s", finite_or_null(r.first_impact)},
      {"outcome", std::string(outcome_name(r.outcome))},
      {"t_end", r.t_end},
      {"final_theta", r.final_theta},
      {"stats", {{"rhs", r.stats.rhs}, {"steps", r.stats.steps}, {"rejected", r.stats.rejected},
                 {"events", r.stats.events}}},
      {"wall_s", r.wall_s},
  };
  if (r.outcome == Outcome::failed) out["failure"] = r.failure;
  json devices = json::array();
  for (const DeviceResult& d : r.devices)
    devices.push_back({{"name", d.name},
                       {"peak_elongation_m", d.peak_elongation},
                       {"peak_force_N", d.peak_force},
                       {"work_J", finite_or_null(d.work)},
                       {"fracture_s", finite_or_null(d.fracture_time)}});
  out["devices"] = devices;
  if (r.energy_tracked) {
    const EnergyBalance& e = r.energy;
    out["energy_J"] = {{"initial", e.initial}, {"final", e.final}, {"ground_input", e.ground},
                       {"viscous", e.viscous}, {"damper", e.damper}, {"impacts", e.impacts},
                       {"balance_residual", e.residual()}};
  }
  return out;
}

void write_text(const std::filesystem::path& file, const std::string& text) {
  const std::filesystem::path tmp = file.string() + ".tmp";
  std::ofstream out(tmp);
  out << text;
  out.close();
  std::error_code ec;
  if (out) std::filesystem::rename(tmp, file, ec);
  if (!out || ec) {
    std::filesystem::remove(tmp, ec);
    throw InputError(fmt::format("{}: cannot write", file.string()));
  }
}

Progress::Progress(bool enabled) : enabled_(enabled && ::isatty(2) != 0), start_(std::chrono::steady_clock::now()) {}

void Progress::operator()(std::size_t done, std::size_t total) {
  if (!enabled_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double eta = done > 0 ? elapsed * static_cast<double>(total - done) / static_cast<double>(done) : 0;
  const int width = 30, filled = static_cast<int>(width * done / std::max<std::size_t>(total, 1));
  fmt::print(stderr, "\r[{}{}] {}/{} jobs, {:.1f} s, ETA {:.1f} s ", std::string(filled, '#'),
             std::string(width - filled, ' '), done, total, elapsed, eta);
  if (done == total) fmt::print(stderr, "\n");
}

int thread_count(int requested) {
  if (requested < 0) throw InputError(fmt::format("--threads {}: must be at least 1 (0: every core)", requested));
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int most = 4 * cores;  // beyond this, threads only wait for each other
  if (requested > most) {
    spdlog::warn("--threads {}: this machine has {} cores; running {} threads", requested, cores, most);
    return most;
  }
  return requested > 0 ? requested : cores;
}

}  // namespace rocking::app
