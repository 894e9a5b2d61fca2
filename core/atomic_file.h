// Crash-safe file writes: every output is written to a temp file beside its final name,
// flushed to disk and renamed over it, so a reader sees the old file or the new one, never half.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/status.h"

namespace mesocap {

// Calls `write(temp)` with a temp path in the same folder that keeps `path`'s extension (so
// writers that choose a format by extension still work), then fsyncs and renames it to `path`.
// On any failure the temp file is removed and `path` is untouched. A run killed mid-write (Ctrl-C)
// cannot remove its temp: the first write into a folder removes those of runs that have ended.
Status WriteFileAtomically(const std::filesystem::path& path,
                           const std::function<Status(const std::filesystem::path& temp)>& write);

Status WriteTextAtomically(const std::filesystem::path& path, std::string_view text);

// Appends one line and fsyncs it: used for journals, where a crash may cut only the last line.
Status AppendLineDurably(const std::filesystem::path& path, std::string_view line);

// Writes all `size` bytes at `offset` of file descriptor `fd` (pwrite, resumed after a partial
// write or EINTR): 0, or the errno of the failure (EIO for a write that wrote nothing).
int WriteAllAt(int fd, const void* bytes, size_t size, uint64_t offset);

// A file written in parts at their offsets (pwrite), for large outputs written in bands: each
// part can start its write-back to disk at once (StartWriteBack), so the fsync that
// WriteFileAtomically ends with finds little left to do. Errors are remembered: ok() and Close()
// report them (errno).
class OutputFile {
 public:
  explicit OutputFile(const std::filesystem::path& path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  bool ok() const { return fd_ >= 0 && error_ == 0; }
  void WriteAt(uint64_t offset, const void* bytes, size_t size);
  // Starts writing [offset, offset + size) to disk, without waiting for it.
  void StartWriteBack(uint64_t offset, size_t size);
  bool Close();  // false if any write or the close failed, errno set

 private:
  int fd_ = -1;
  std::atomic<int> error_{0};  // parts may be written from several threads at once
};

// Reads a whole file; error names it.
StatusOr<std::string> ReadTextFile(const std::filesystem::path& path);

// fsync a file or a folder by path (a folder after a rename makes the rename durable).
Status SyncPath(const std::filesystem::path& path);

// Output folders that appear whole or not at all: the work goes into StagingFolderFor(out), a
// hidden sibling `.NAME.partial-PID@HOST`, and PublishStagingFolder moves it onto `out` (missing or an
// empty folder) and makes the rename durable. An interrupted run leaves nothing under `out`.
std::filesystem::path StagingFolderFor(const std::filesystem::path& out);
Status PublishStagingFolder(const std::filesystem::path& staging, const std::filesystem::path& out);

// The same as an object: Begin makes an empty staging folder for `out` (absolute, a trailing "/"
// dropped); Publish moves it into place; the destructor removes it unless published, also when
// an exception unwinds or a worker fails, so no exit path leaves a half-built folder behind.
class StagingFolder {
 public:
  static StatusOr<StagingFolder> Begin(const std::filesystem::path& out);
  StagingFolder(StagingFolder&& other) noexcept;
  StagingFolder& operator=(StagingFolder&&) = delete;
  ~StagingFolder();

  const std::filesystem::path& path() const { return staging_; }  // write here
  const std::filesystem::path& out() const { return out_; }
  // `out` must be missing or empty; with `replace`, an existing `out` is swapped out and removed
  // (a re-run's outputs: readers see the old folder or the new one, never a mixture).
  Status Publish(bool replace = false);

 private:
  StagingFolder(std::filesystem::path out, std::filesystem::path staging);
  std::filesystem::path out_, staging_;
  bool published_ = false;
};

// Several output files that appear together or not at all: Stage writes each to a hidden temp
// beside its final name; Commit moves each file already there aside to a hidden backup and
// renames the new one into place, in staging order; when a rename fails, every earlier file of
// the set is put back, so the old set stays whole. A run killed between the renames (the machine
// stopping) can leave a mixture: stage the report last, so it marks a complete set, and the next
// write into the folder puts back a backup whose new file never arrived. Files staged but not
// committed are removed when the set is destroyed.
class OutputFileSet {
 public:
  OutputFileSet() = default;
  OutputFileSet(const OutputFileSet&) = delete;
  OutputFileSet& operator=(const OutputFileSet&) = delete;
  ~OutputFileSet();

  // Calls write(temp); errors name `path`, not the temp.
  Status Stage(const std::filesystem::path& path,
               const std::function<Status(const std::filesystem::path& temp)>& write);
  Status Commit();

 private:
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged_;  // temp, final
};

}  // namespace mesocap
