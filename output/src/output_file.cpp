#include <sage/output/output_file.hpp>
#include <sage/output/vtk_writer.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace sage::output {

namespace {

namespace fs = std::filesystem;

/// A hidden name beside `path`, unique to this process: ".NAME.PID.tmp".
fs::path temporary_beside(const std::string& path) {
  const fs::path target(path);
  return target.parent_path() / ("." + target.filename().string() + "." + std::to_string(::getpid()) + ".tmp");
}

}  // namespace

void check_writable(const std::string& path) {
  const fs::path target(path);
  std::error_code ec;
  if (target.filename().empty() || fs::is_directory(target, ec))
    throw OutputError(path + ": is a folder, not a file name");
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  if (!fs::is_directory(folder, ec)) throw OutputError(path + ": the folder " + folder.string() + " does not exist");
  const fs::path probe = temporary_beside(path);
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd < 0)
    throw OutputError(path + ": cannot write in the folder " + folder.string() + " (" + std::strerror(errno) + ")");
  ::close(fd);
  fs::remove(probe, ec);
}

void write_atomically(const std::string& path, const std::function<void(const std::string& temporary)>& write) {
  check_writable(path);
  const fs::path temporary = temporary_beside(path);
  try {
    write(temporary.string());
    std::error_code ec;
    fs::rename(temporary, path, ec);
    if (ec) throw OutputError(path + ": cannot replace the file (" + ec.message() + ")");
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
}

}  // namespace sage::output
