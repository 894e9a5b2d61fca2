#include "core/logging.h"

#include <spdlog/sinks/stdout_color_sinks.h>

namespace mesocap {

void InitLogging(int verbosity) {
  auto logger = spdlog::stderr_color_mt("mesocap");
  logger->set_pattern("%^%l%$: %v");
  logger->set_level(verbosity <= 0 ? spdlog::level::warn
                    : verbosity == 1 ? spdlog::level::info
                                     : spdlog::level::debug);
  spdlog::set_default_logger(logger);
}

}  // namespace mesocap
