#pragma once
/// @file
/// The project's one worker pool. Every parallel loop (rendering a study, analysing its trials,
/// comparing them, discovery's fits, scoring) runs through ParallelFor, so the rule for the
/// number of threads and the handling of a worker's exception are written once.
///
/// Written on std::thread rather than oneTBB: ThreadSanitizer (tools/sanitize thread) sees the
/// synchronisation of std::thread and std::mutex, but not that inside an uninstrumented libtbb,
/// whose every handover it would report as a race or have to suppress wholesale.

#include <cstddef>
#include <functional>

namespace hoof::core {

/// The number of threads that `jobs` asks for: `jobs` itself when positive, otherwise (0, the
/// command-line default "all cores") the machine's hardware threads, at least 1.
int ResolveJobs(int jobs);

/// Calls fn(i) once for each i in [0, n), on min(ResolveJobs(jobs), n) threads, the calling
/// thread among them; indices are handed out in increasing order as threads come free. Returns
/// when every call has returned. If a call throws, no further index is started, the threads are
/// joined, and the first exception is rethrown here (one escaping a thread would end the program
/// through std::terminate). fn must be safe to call from several threads at once.
void ParallelFor(std::size_t n, int jobs, const std::function<void(std::size_t)>& fn);

}  // namespace hoof::core
