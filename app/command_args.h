// Every subcommand's options (app/<verb>_args.h), for the two places that list them all: the
// front's command line (command_line.cc) and the module's dispatch (commands_module.cc).
#pragma once

#include "app/calibrate_args.h"
#include "app/calibrate_camera_args.h"
#include "app/cameras_args.h"
#include "app/capture_args.h"
#include "app/console_args.h"
#include "app/coverage_args.h"
#include "app/decorate_args.h"
#include "app/demo_args.h"
#include "app/evaluate_args.h"
#include "app/export_args.h"
#include "app/fit_ptm_args.h"
#include "app/import_args.h"
#include "app/layout_args.h"
#include "app/lights_args.h"
#include "app/process_args.h"
#include "app/reconstruct_args.h"
#include "app/relight_args.h"
#include "app/simulate_args.h"
#include "app/synth_args.h"
