// Parts of mesocap built as modules and loaded with dlopen when first needed, so that the
// libraries they bring are mapped only by the runs that use them: the image codec over
// OpenImageIO (core/image_codec.h) and the commands' runs (app/commands_module.cc).
#pragma once

#include <string>

#include "core/status.h"

namespace mesocap {

// The address of `symbol` in the module file `module_name`, looked for beside the running
// executable (installed, or in the build tree), then at `build_path` when not empty (the build's
// copy, for tests and benchmarks in other folders). The module stays loaded for the life of the
// process. An error says where it looked and why each candidate failed.
StatusOr<void*> LoadModuleSymbol(const std::string& module_name, const std::string& build_path, const char* symbol);

// The object a module's factory `symbol` (a function T* ()) returns. Callers keep it in a
// function-level static, so the module is looked for once.
template <typename T>
StatusOr<T*> LoadModuleObject(const std::string& module_name, const std::string& build_path, const char* symbol) {
  auto factory = LoadModuleSymbol(module_name, build_path, symbol);
  if (!factory.ok()) return factory.status();
  return reinterpret_cast<T* (*)()>(*factory)();
}

}  // namespace mesocap
