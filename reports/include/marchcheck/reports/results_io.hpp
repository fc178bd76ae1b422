// Result files: flat dotted metrics as JSON, written atomically.
#pragma once

#include <map>
#include <string>

namespace marchcheck::reports {

// Writes text through a temporary file in the same folder renamed into place: a reader never sees half a file.
// Throws std::runtime_error naming the path.
void write_text_atomically(const std::string& path, const std::string& text);

// {"metric.name": value, ...} sorted by name; non-finite values are written as null.
std::string metrics_json(const std::map<std::string, double>& metrics);

}  // namespace marchcheck::reports
