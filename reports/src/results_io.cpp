#include "marchcheck/reports/results_io.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace marchcheck::reports {

void write_text_atomically(const std::string& path, const std::string& text) {
  const std::filesystem::path target(path);
  auto tmp = target;
  tmp.replace_filename("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()));
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot create the file");
    out << text;
    out.flush();
    if (!out) {
      out.close();
      std::filesystem::remove(tmp);
      throw std::runtime_error(path + ": cannot write the file");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, target, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    throw std::runtime_error(path + ": cannot move the finished file into place: " + ec.message());
  }
}

std::string metrics_json(const std::map<std::string, double>& metrics) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [name, value] : metrics) j[name] = std::isfinite(value) ? nlohmann::ordered_json(value) : nullptr;
  return j.dump(2) + "\n";
}

}  // namespace marchcheck::reports
