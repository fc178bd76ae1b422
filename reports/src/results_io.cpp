#include "marchcheck/reports/results_io.hpp"

#include "marchcheck/march/atomic_file.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <stdexcept>

namespace marchcheck::reports {

void write_text_atomically(const std::string& path, const std::string& text) {
  march::write_atomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot create " + tmp + " (missing folder or no permission?)");
    out << text;
    out.close();
    if (!out) throw std::runtime_error("cannot write " + tmp + " (disk full?)");
  });
}

std::string metrics_json(const std::map<std::string, double>& metrics) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [name, value] : metrics) j[name] = std::isfinite(value) ? nlohmann::ordered_json(value) : nullptr;
  return j.dump(2) + "\n";
}

}  // namespace marchcheck::reports
