// A study's output folder as the study owns it: one study at a time (a lock
// the operating system releases when the process ends, however it ends), the
// inputs it was run with (DIR/inputs.txt, which --resume must match), and no
// folder standing where an output file goes.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace rocking::app {

// Holds DIR/.lock (flock) for its lifetime; InputError when another study
// holds it.
class FolderLock {
 public:
  explicit FolderLock(const std::filesystem::path& dir);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

// What makes two studies the same, one "key = value" line each: the kind,
// the scene after its overrides, every record with its size and a hash of
// its bytes, and each further input (IM, levels, variants, integrator and
// tolerances) as given.
std::string study_inputs(const std::string& kind, const std::string& scene_text, const std::vector<std::string>& records,
                         const std::vector<std::pair<std::string, std::string>>& settings);

// Writes DIR/inputs.txt (a fresh study), or with `resume` checks that it
// holds `inputs` (InputError naming the first line that differs, or the
// missing file).
void record_inputs(const std::filesystem::path& dir, const std::string& inputs, bool resume);

// Where --resume reads the rows of `file`: the file itself when its run ended
// (finished or stopped), else the .partial file a killed run left.
std::filesystem::path resume_source(const std::filesystem::path& file);

// InputError naming the first of `files` (in DIR) that is a folder.
void check_outputs_free(const std::filesystem::path& dir, const std::vector<std::string>& files);

}  // namespace rocking::app
