#include "rbaa/io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <locale>

#include "rbaa/error.hpp"

namespace rbaa {

namespace {

std::string parent_directory(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

// Why the file cannot be created, worded for a user: a missing directory is the common case.
std::string cannot_write(const std::string& path, int error) {
  const std::string dir = parent_directory(path);
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) {
    return "cannot write " + path + ": directory '" + dir + "' does not exist";
  }
  return "cannot write " + path + ": " + std::strerror(error);
}

// fsync through a fresh descriptor: fsync acts on the file, not on the descriptor that wrote.
bool sync_path(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), flags);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  ::close(fd);
  return ok;
}

}  // namespace

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& writer) {
  if (path.empty()) throw InputError("cannot write a file with an empty name");
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(cannot_write(path, errno));
    out.imbue(std::locale::classic());
    out.precision(17);
    try {
      writer(out);
      out.flush();
    } catch (...) {
      out.close();
      std::remove(tmp.c_str());
      throw;
    }
    if (!out) {
      const int error = errno;
      out.close();
      std::remove(tmp.c_str());
      throw InputError("cannot write " + path + ": " + std::strerror(error) + " (disk full?)");
    }
    out.close();
    if (out.fail()) {
      std::remove(tmp.c_str());
      throw InputError("cannot write " + path + ": closing the file failed");
    }
  }
  if (!sync_path(tmp, O_RDONLY)) {
    const int error = errno;
    std::remove(tmp.c_str());
    throw InputError("cannot write " + path + ": fsync failed: " + std::strerror(error));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    std::remove(tmp.c_str());
    throw InputError("cannot write " + path + ": renaming " + tmp +
                     " failed: " + std::strerror(error));
  }
  // Makes the rename itself durable; a failure here loses nothing already on disk, so it is not
  // worth an error (some file systems refuse fsync on directories).
  sync_path(parent_directory(path), O_RDONLY | O_DIRECTORY);
}

}  // namespace rbaa
