#include "marchcheck/files/atomic_file.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace marchcheck::files {

std::string temp_name(const std::string& path) {
  std::filesystem::path tmp(path);
  tmp.replace_filename("." + tmp.filename().string() + ".tmp-" + std::to_string(::getpid()) +
                       tmp.extension().string());
  return tmp.string();
}

void write_atomically(const std::string& path, const std::function<void(const std::string& temp)>& write) {
  const std::string tmp = temp_name(path);
  std::error_code ignored;  // cleanup is best effort: the first error is the one to report
  try {
    write(tmp);
  } catch (const std::exception& e) {
    std::filesystem::remove(tmp, ignored);
    throw std::runtime_error(path + ": " + e.what());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ignored);
    throw std::runtime_error(path + ": cannot move the finished file into place: " + ec.message());
  }
}

void write_bytes_atomically(const std::string& path, std::string_view bytes) {
  write_atomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot create " + tmp + " (missing folder or no permission?)");
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();  // the last buffer reaches the disk here: its failure counts too
    if (!out) throw std::runtime_error("cannot write " + tmp + " (disk full?)");
  });
}

}  // namespace marchcheck::files
