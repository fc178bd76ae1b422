// Whole files or none: every image, mesh and result file the project writes goes through here.
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace marchcheck::files {

// "dir/name.ext" -> "dir/.name.ext.tmp-PID.ext": same folder (so the rename is atomic), same extension (image
// writers pick the format from it), hidden, and distinct per process.
std::string temp_name(const std::string& path);

// Calls write(temp) to fill temp_name(path), then renames it over path. If write throws or the rename fails,
// the temporary is removed, whatever was at path stays as it was, and std::runtime_error "PATH: problem" is
// thrown (problem: the writer's message).
void write_atomically(const std::string& path, const std::function<void(const std::string& temp)>& write);

// The bytes as the whole of path, or nothing: a write that fails at any point (a full disk, a file-size limit,
// at close) throws "PATH: problem" and leaves whatever was at path.
void write_bytes_atomically(const std::string& path, std::string_view bytes);

}  // namespace marchcheck::files
