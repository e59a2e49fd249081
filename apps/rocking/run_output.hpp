// What a run writes: the history (CSV, streamed as the run goes) and the
// summary (JSON). Shared by the commands that run scenes.
#pragma once
#include <rocking/eigen.hpp>
#include <nlohmann/json.hpp>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>
import rocking.simulation;
import rocking.report;

namespace rocking::app {

// Streams every Response to DIR/history.csv.partial, renamed to history.csv
// when closed whole (a run that fails or stops leaves whole rows up to
// there; a write that fails leaves the .partial file): a header row of
// "name [unit]", the columns of rocking::history_columns (the schema's
// history quantities the model reports, then each device's by its name; or
// those chosen). A broken device's fields are empty after its fracture.
class HistoryCsv : public rocking::HistoryObserver {
 public:
  // The model's default columns unless given (rocking::history_columns).
  HistoryCsv(const std::filesystem::path& file, const rocking::ContactModel& model)
      : HistoryCsv(file, model, rocking::history_columns(model)) {}
  HistoryCsv(const std::filesystem::path& file, const rocking::ContactModel& model, rocking::HistoryColumns columns);
  ~HistoryCsv() override;
  HistoryCsv(const HistoryCsv&) = delete;
  HistoryCsv& operator=(const HistoryCsv&) = delete;
  void close();  // flushes and renames; RunError if the disk refused (the .partial file stays)

 protected:
  void row(const rocking::Response& r, const std::vector<double>& values) override;

 private:
  void print_row(const std::vector<double>& values);
  void flush();  // writes the buffered rows; RunError if the disk refused, the file cut back to its whole rows
  bool write_whole();  // writes and flushes the buffer; false (the file cut back to committed_ bytes) if refused
  static constexpr std::size_t flush_size = 1 << 16;  // rows leave in blocks of about this many bytes
  std::vector<char> buffer_;  // rows not yet written: its first used_ bytes
  std::size_t used_ = 0;
  std::FILE* file_ = nullptr;
  long committed_ = 0;  // bytes of the file in whole rows (and the header), written and flushed
  std::string path_, partial_;
};

// Room on the disk for a file written at the end (a run's summary): taken
// when made, so that a history that fills the disk leaves room for the
// summary that says so. write() puts the text in it and renames it to its
// name (RunError naming the file if even that fails); a file never written is
// removed.
class ReservedFile {
 public:
  ReservedFile(std::filesystem::path file, std::size_t bytes);
  ~ReservedFile();
  ReservedFile(const ReservedFile&) = delete;
  ReservedFile& operator=(const ReservedFile&) = delete;
  void write(const std::string& text);

 private:
  std::filesystem::path file_, room_;
  int fd_ = -1;
};

// Creates DIR (and parents) or fails with a one-line InputError.
void make_output_dir(const std::filesystem::path& dir);

// --- shared by the commands that run many jobs --------------------------------

// A progress bar with an ETA on stderr, only when enabled and stderr is a terminal.
class Progress {
 public:
  explicit Progress(bool enabled);
  void operator()(std::size_t done, std::size_t total);

 private:
  bool enabled_;
  std::chrono::steady_clock::time_point start_;
};

// --threads N: N, or every core for 0; InputError below 0; above four
// threads a core, that many, with a warning.
int thread_count(int requested);

}  // namespace rocking::app
