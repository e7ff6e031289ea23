#pragma once
/// @file
/// Ctrl-C (and SIGTERM, SIGHUP) without partial output. Every output is written to a temporary
/// beside its target and renamed into place when complete (atomic_file.h); an interrupt then
/// only has to remove the temporaries that are still open and end the child processes still
/// running. This file keeps the list of both, and a thread of its own acts on the signal.

#include <sys/types.h>

#include <filesystem>

#include <spawn.h>

namespace hoof::io {

/// Records a temporary file or folder that an interrupt must remove. TemporaryPathFor() records
/// its paths itself; code that makes a temporary folder another way records it here.
void TrackTemporary(const std::filesystem::path& path);
/// Forgets a temporary: it was committed (renamed into place) or removed.
void UntrackTemporary(const std::filesystem::path& path);

/// Held while a temporary, or a folder on the way to one, is made: a file opened or copied to, a
/// folder created, a temporary renamed. An interrupt waits for the ones under way and lets none
/// start after, so a temporary it removes is not made again before the process ends. Files made
/// inside a temporary folder need none: once the folder is gone they cannot be made, and one
/// made while it is being removed is removed on the next pass.
class CreatingTemporary {
 public:
  CreatingTemporary();
  ~CreatingTemporary();
  CreatingTemporary(const CreatingTemporary&) = delete;
  CreatingTemporary& operator=(const CreatingTemporary&) = delete;
};

/// Records a child process an interrupt must end (SIGKILL, then waited for), and forgets it once
/// it was waited for. Start and record it while holding a CreatingTemporary, so an interrupt
/// never misses a child that is about to write a temporary.
void TrackChild(pid_t pid);
void UntrackChild(pid_t pid);

/// Gives a child started with posix_spawn the default signal handling and an empty signal mask,
/// so Ctrl-C at the terminal reaches it (HandleInterrupts() blocks the signals in this process).
/// `attributes` must be initialised.
void ResetChildSignals(posix_spawnattr_t& attributes);

/// When an interrupt is under way, waits for it to end the process (with its own exit code);
/// returns at once otherwise. Call before reporting a failure: one the interrupt caused in this
/// thread (a child it ended, a temporary it removed under a writer) is then not reported as the
/// job's own error with exit code 1.
void YieldToInterrupt();

/// Call first in main(), before any other thread starts. SIGINT, SIGTERM and SIGHUP are then
/// blocked in every thread and taken by one thread of their own, which waits for the temporaries
/// being made (CreatingTemporary), ends the tracked children, removes the tracked temporaries,
/// says so on stderr and ends the process with
/// exit code 128 + the signal's number (130 for Ctrl-C). Outputs already renamed into place are
/// complete and stay; no partial output is left.
void HandleInterrupts();

}  // namespace hoof::io
