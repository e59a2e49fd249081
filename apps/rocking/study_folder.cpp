#include "study_folder.hpp"
#include "run_output.hpp"
#include <fmt/format.h>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>
import rocking.errors;
import rocking.study_files;

namespace rocking::app {

namespace fs = std::filesystem;

FolderLock::FolderLock(const fs::path& dir) {
  const fs::path file = dir / ".lock";
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw RunError(fmt::format("{}: cannot open the study's lock: {}", file.string(), std::strerror(errno)));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw InputError(fmt::format("--out {}: another study is writing there (it holds {}); wait for it or choose "
                                 "another --out",
                                 dir.string(), file.string()));
  }
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

namespace {

// FNV-1a over a file's bytes: enough to tell a changed record from the same one.
std::uint64_t file_hash(const std::string& path, std::uintmax_t& size) {
  std::ifstream in(path, std::ios::binary);
  std::uint64_t h = 14695981039346656037ull;
  size = 0;
  char buffer[65536];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) h = (h ^ static_cast<unsigned char>(buffer[i])) * 1099511628211ull;
    size += static_cast<std::uintmax_t>(in.gcount());
  }
  return h;
}

// One line: newlines of a value (the scene's TOML) written as \n.
std::string one_line(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '\n' ? std::string("\\n") : std::string(1, c);
  return out;
}

}  // namespace

std::string study_inputs(const std::string& kind, const std::string& scene_text, const std::vector<std::string>& records,
                         const std::vector<std::pair<std::string, std::string>>& settings) {
  std::string out = fmt::format("# the inputs of this folder's study; --resume continues it only with the same\n"
                                "kind = {}\nscene = {}\n",
                                kind, one_line(scene_text));
  for (const std::string& r : records) {
    std::uintmax_t size = 0;
    const std::uint64_t h = file_hash(r, size);
    out += fmt::format("record = {} ({} bytes, fnv1a {:016x})\n", one_line(fs::absolute(r).lexically_normal().string()),
                       size, h);
  }
  for (const auto& [key, value] : settings) out += fmt::format("{} = {}\n", key, one_line(value));
  return out;
}

void record_inputs(const fs::path& dir, const std::string& inputs, bool resume) {
  const fs::path file = dir / "inputs.txt";
  if (!resume) {
    write_text(file, inputs);
    return;
  }
  std::ifstream in(file);
  if (!in)
    throw InputError(fmt::format("--resume: {} not found: the folder does not say what study it holds; run it afresh",
                                 file.string()));
  std::stringstream had_text;
  had_text << in.rdbuf();
  std::istringstream had(had_text.str()), now(inputs);
  std::string a, b;
  for (int n = 1;; ++n) {
    const bool more_a = static_cast<bool>(std::getline(had, a)), more_b = static_cast<bool>(std::getline(now, b));
    if (!more_a && !more_b) return;
    if (a != b || more_a != more_b) {
      const std::string key = (more_a ? a : b).substr(0, (more_a ? a : b).find(" = "));
      throw InputError(fmt::format("--resume: {}:{}: the interrupted study had another {} than this command; give "
                                   "the same inputs, or another --out for a new study",
                                   file.string(), n, key));
    }
  }
}

fs::path resume_source(const fs::path& file) {
  std::error_code ec;
  return fs::exists(file, ec) ? file : fs::path(file.string() + ".partial");
}

void check_outputs_free(const fs::path& dir, const std::vector<std::string>& files) {
  std::error_code ec;
  for (const std::string& f : files)
    if (fs::is_directory(dir / f, ec))
      throw InputError(fmt::format("{}: a folder stands where the study writes this file; move it or choose another "
                                   "--out",
                                   (dir / f).string()));
}

}  // namespace rocking::app
