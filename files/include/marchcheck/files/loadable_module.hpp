// Libraries only some commands use, loaded by those commands alone: a module (a shared object beside the library
// that loads it) pays its dynamic loading when first used, not at every start-up.
#pragma once

#include <string>

namespace marchcheck::files {

// The address of `entry` in module_file, loaded (once; dlopen counts) from the folder of the library holding
// `anchor`, any function of that library: in the build tree as once installed. RTLD_LOCAL: the module's libraries
// stay out of the program's symbol scope. Throws std::runtime_error naming the file when it cannot be loaded or
// lacks the entry.
void* module_entry(const void* anchor, const std::string& module_file, const char* entry);

// The table of functions a module's entry, `extern "C" const Table* entry()`, returns.
template <class Table>
const Table& module_table(const void* anchor, const std::string& module_file, const char* entry) {
  return *reinterpret_cast<const Table* (*)()>(module_entry(anchor, module_file, entry))();
}

}  // namespace marchcheck::files
