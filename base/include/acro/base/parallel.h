#pragma once

// One parallel-for for the whole project (docs/design.md, "Threads"): items taken in order from a
// shared counter by `threads` workers, the calling thread one of them; the first exception thrown
// by any item stops the others from taking new items and is rethrown in the caller.

#include <functional>

namespace acro {

/// The number of workers for a request: `requested` when positive, else the machine's cores
/// (at least 1).
int WorkerThreads(int requested);

/// Calls body(i) for i = 0 … count − 1 on WorkerThreads(threads) threads. `keep_going`, when
/// given, is asked before each item: false stops taking new ones (the running ones finish).
void ParallelFor(int count, int threads, const std::function<void(int)>& body,
                 const std::function<bool()>& keep_going = {});

}  // namespace acro
