#include "run_output.hpp"
#include <rocking/decimal.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include "log.hpp"
#include <cerrno>
#include <system_error>
#include <cmath>
#include <cstring>
#include <algorithm>
#include <fstream>
#include <thread>
#include <fcntl.h>
#include <unistd.h>
import rocking.report;
import rocking.errors;
import rocking.study_files;

namespace rocking::app {

HistoryCsv::HistoryCsv(const std::filesystem::path& file, const ContactModel& model, HistoryColumns chosen)
    : HistoryObserver(model, std::move(chosen)), path_(file.string()), partial_(path_ + ".partial") {
  std::error_code ec;
  for (const std::string& p : {path_, partial_})
    if (std::filesystem::is_directory(p, ec))
      throw InputError(fmt::format("{}: a folder stands where the history goes; move it or choose another --out", p));
  file_ = std::fopen(partial_.c_str(), "w");
  if (file_ == nullptr) throw RunError(fmt::format("{}: cannot write: {}", partial_, std::strerror(errno)));
  // Rows are buffered here (buffer_), in whole rows: stdio holds none back,
  // so that what a full disk refused is known to the byte.
  std::setvbuf(file_, nullptr, _IONBF, 0);
  const std::string header = fmt::format("{}\n", fmt::join(columns().headers(), ","));
  if (std::fputs(header.c_str(), file_) >= 0 && std::fflush(file_) == 0) committed_ = static_cast<long>(header.size());
}

HistoryCsv::~HistoryCsv() {
  if (file_ == nullptr) return;  // closed
  write_whole();  // what a run that threw had reached, into the .partial file, in whole rows
  std::fclose(file_);
}

bool HistoryCsv::write_whole() {
  if (std::ferror(file_) == 0 && (used_ == 0 || std::fwrite(buffer_.data(), 1, used_, file_) == used_) &&
      std::fflush(file_) == 0) {
    committed_ += static_cast<long>(used_);
    used_ = 0;
    return true;
  }
  // A full disk took part of a row: the file keeps its whole rows only.
  const int error = errno;
  if (::ftruncate(::fileno(file_), committed_) == 0) std::fseek(file_, committed_, SEEK_SET);
  used_ = 0;
  errno = error;
  return false;
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
  if (!write_whole())
    throw RunError(fmt::format("{}: cannot write: {} (the whole rows written are in {})", path_, std::strerror(errno),
                               partial_));
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

ReservedFile::ReservedFile(std::filesystem::path file, std::size_t bytes)
    : file_(std::move(file)), room_(file_.string() + ".reserved") {
  fd_ = ::open(room_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw RunError(fmt::format("{}: cannot write: {}", file_.string(), std::strerror(errno)));
  (void)::posix_fallocate(fd_, 0, static_cast<off_t>(bytes));  // a disk already full gives no room: write() says so
}

ReservedFile::~ReservedFile() {
  if (fd_ < 0) return;  // written
  ::close(fd_);
  std::error_code ec;
  std::filesystem::remove(room_, ec);
}

void ReservedFile::write(const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::pwrite(fd_, text.data() + done, text.size() - done, static_cast<off_t>(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  int error = done == text.size() ? 0 : errno;
  if (error == 0 && ::ftruncate(fd_, static_cast<off_t>(text.size())) != 0) error = errno;
  if (::close(fd_) != 0 && error == 0) error = errno;
  fd_ = -1;
  std::error_code ec;
  if (error == 0) std::filesystem::remove(file_, ec);
  if (error == 0) std::filesystem::rename(room_, file_, ec);
  if (error != 0 || ec) {
    std::filesystem::remove(room_, ec);
    throw RunError(fmt::format("{}: cannot write: {}", file_.string(), error != 0 ? std::strerror(error) : ec.message()));
  }
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
  if (w.capped) log::warn("--threads {}: this machine has {} cores; running {} threads", requested, w.cores, w.threads);
  return w.threads;
}

}  // namespace rocking::app
