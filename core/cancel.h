// Ctrl-C for every command: SIGINT (and SIGTERM) only set a flag. Long work sees it at its next
// progress report (ReportProgress and ProgressBar::Update return false) and returns
// Status::Cancelled(); unwinding removes staging folders and scratch files (their destructors),
// and the command exits 3 saying so. A second Ctrl-C kills the process at once.
#pragma once

namespace mesocap {

// Installs the handler (once; the commands module calls it before any command runs).
void InstallCancelHandler();
// Whether the user asked to stop.
bool CancelRequested();

}  // namespace mesocap
