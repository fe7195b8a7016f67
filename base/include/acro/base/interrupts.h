#pragma once

// Ctrl-C and SIGTERM for a program that writes outputs: one thread of its own receives both,
// removes every unfinished output (acro/base/temporaries.h), stops the registered children, says
// so in one line on stderr and ends the program with 128 + the signal (130, 143). Every door that
// runs long work from a terminal (the command line, `acrolab live`) installs it first thing.
//
// A signal that arrives before InstallInterruptCleanup has run (while the dynamic loader is still
// mapping the libraries, before main) ends the program with the default action: 143 or 130 with
// nothing written yet, and no line (tests/robustness: SigtermAtAnyInstantEndsABatchCleanly). The
// tests that time a signal into the work wait for the mask (/proc/PID/status SigBlk) first.

namespace acro {

/// Blocks SIGINT and SIGTERM in the calling thread (every thread started later inherits the mask)
/// and starts the thread that waits for them. Call once, at the top of main, before any thread.
void InstallInterruptCleanup();

/// True once Ctrl-C or SIGTERM has arrived (the interrupt thread is cleaning up and will exit).
bool InterruptReceived();

/// `status` once the command has returned, unless the interrupt thread has begun: then this never
/// returns and that thread ends the program with 130 or 143 when its clean-up is done.
int ExitStatusUnlessInterrupted(int status);

}  // namespace acro
