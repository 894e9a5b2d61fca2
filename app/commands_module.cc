// The commands module (libmesocap_commands.so): every subcommand's run, with the libraries they
// need (OpenCV, Ceres, libgphoto2, TBB ...), loaded by the front executable (app/main.cc) once
// the command line has been parsed.
#include <cstdio>
#include <cstring>
#include <exception>

#include "app/command_args.h"
#include "app/commands.h"
#include "core/cancel.h"
#include "core/image_io.h"
#include "core/logging.h"
#include "core/pixel_memory.h"
#include "core/provenance.h"

extern "C" __attribute__((visibility("default"))) int MesocapRunCommand(const char* verb, void* args,
                                                                        size_t args_size,
                                                                        const mesocap::app::GlobalOptions* globals,
                                                                        int argc, char** argv) {
  using namespace mesocap;
  using namespace mesocap::app;
  KeepLargeLibraryBuffersInHeap();
  SetCommandLine(argc, argv);
  InitLogging(globals->verbosity);
  SetMaxImagePixels(int64_t(globals->max_megapixels * 1e6));
  InstallCancelHandler();  // Ctrl-C: every command stops at its next progress check, exit 3
  try {
#define MESOCAP_RUN_IF_CHOSEN(Verb)                                      \
  if (std::strcmp(verb, #Verb) == 0 && args_size == sizeof(Verb##Args)) \
    return Run##Verb(*static_cast<Verb##Args*>(args));
    MESOCAP_FOR_EACH_COMMAND(MESOCAP_RUN_IF_CHOSEN)
#undef MESOCAP_RUN_IF_CHOSEN
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mesocap: internal error: %s\n", e.what());
    return kExitInternal;
  }
  std::fprintf(stderr, "mesocap: internal error: %s is not the commands module of this mesocap (reinstall mesocap)\n",
               kCommandsModuleName);
  return kExitInternal;
}
