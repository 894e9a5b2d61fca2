// What the running process has used so far, for the reports' timing and memory fields.
#pragma once

namespace mesocap {

// CPU seconds of every thread of the process (std::clock): on a shared machine a steadier
// measure of the work than wall time.
double ProcessCpuSeconds();
// The most resident memory the process has held so far (getrusage's ru_maxrss), in MiB.
double PeakMemoryMiB();

}  // namespace mesocap
