#include "run_output.hpp"
#include <rocking/decimal.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
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

HistoryCsv::HistoryCsv(const std::filesystem::path& file, const ContactModel& model, HistoryColumns chosen)
    : HistoryObserver(model, std::move(chosen)), path_(file.string()), partial_(path_ + ".partial") {
  std::error_code ec;
  for (const std::string& p : {path_, partial_})
    if (std::filesystem::is_directory(p, ec))
      throw InputError(fmt::format("{}: a folder stands where the history goes; move it or choose another --out", p));
  file_ = std::fopen(partial_.c_str(), "w");
  if (file_ == nullptr) throw RunError(fmt::format("{}: cannot write: {}", partial_, std::strerror(errno)));
  const std::string header = fmt::format("{}", fmt::join(columns().headers(), ","));
  std::fputs(header.c_str(), file_);
  std::fputs("\n", file_);
}

HistoryCsv::~HistoryCsv() {
  if (file_ == nullptr) return;  // closed
  std::fwrite(buffer_.data(), 1, used_, file_);  // what a run that threw had reached, into the .partial file
  std::fclose(file_);
}

void HistoryCsv::row(const Response&, const std::vector<double>& values) {
  // A full disk ends the run (RunError, exit 3) naming the file; the rows
  // written before stay.
  if (std::ferror(file_) != 0)
    throw RunError(fmt::format("{}: cannot write: {} (the rows written are in {})", path_, std::strerror(errno), partial_));
  try {
    print_row(values);
  } catch (const std::system_error& e) {
    throw RunError(fmt::format("{}: cannot write: {} (the rows written are in {})", path_, e.code().message(), partial_));
  }
}

void HistoryCsv::print_row(const std::vector<double>& values) {
  // Room for the widest row: every value at its widest, or its label.
  const std::size_t room = values.size() * (g9_max_chars + 1) + 1;
  if (buffer_.size() - used_ < room) buffer_.resize(std::max(2 * buffer_.size(), used_ + room + flush_size));
  char* const start = buffer_.data() + used_;
  char* p = start;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) *p++ = ',';
    const auto& q = columns().columns[i].quantity;
    const std::string_view label = q ? value_label(*q, values[i]) : std::string_view();
    if (!label.empty()) {
      std::memcpy(p, label.data(), label.size());
      p += label.size();
    } else if (!std::isnan(values[i])) {  // nothing for a value that is none (a broken device's)
      p = write_g9(p, values[i]);
    }
  }
  *p++ = '\n';
  used_ += static_cast<std::size_t>(p - start);
  if (used_ >= flush_size) flush();
}

void HistoryCsv::flush() {
  if (used_ > 0 && std::fwrite(buffer_.data(), 1, used_, file_) != used_)
    throw RunError(fmt::format("{}: cannot write: {} (the rows written are in {})", path_, std::strerror(errno), partial_));
  used_ = 0;
}

void HistoryCsv::close() {
  if (file_ == nullptr) return;
  flush();
  const bool bad = std::ferror(file_) != 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (bad || !closed)
    throw RunError(fmt::format("{}: cannot write: {} (the rows written are in {})", path_, std::strerror(errno), partial_));
  std::error_code ec;
  // The previous run's history goes first, as write_text does (rocking.study_files):
  // replacing it by rename would make ext4 write the new one out to disk first.
  std::filesystem::remove(path_, ec);
  std::filesystem::rename(partial_, path_, ec);
  if (ec) throw RunError(fmt::format("{}: cannot write: {} (the rows are in {})", path_, ec.message(), partial_));
}

void make_output_dir(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw InputError(fmt::format("{}: cannot create the output folder: {}", dir.string(),
                                 ec ? ec.message() : "not a folder"));
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
  const WorkerThreads w = worker_threads(requested, "--threads");
  if (w.capped) spdlog::warn("--threads {}: this machine has {} cores; running {} threads", requested, w.cores, w.threads);
  return w.threads;
}

}  // namespace rocking::app
