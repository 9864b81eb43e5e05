// An environmental program as a child process speaking vlab's protocol (libs/comm, the slave side
// every program in vlab's ENVIRO links), over the transport the .e file names:
//   files  — `.to_field<K>.0` / `.from_field<K>.0` in the working directory, turn-taking with a
//            SysV semaphore pair of key K (the program gets `-k K -ext K.0`);
//   memory — a 60 000-byte SysV segment of key K−1 (50 000 bytes to the program, 10 000 back) and
//            the same semaphores (`-k K`);
//   pipes  — the program's stdin and stdout, a byte 0x01 from it to say it is ready.
// The text is the same on all three (docs/environment.md). lpfg itself speaks only files and
// hangs on the others; the program's library defaults to pipes.
#pragma once
#include <functional>
#include <memory>
#include <string>

#include "runtime/Environment.h"

namespace lcjit::runtime {

struct ChildProgramOptions {
  // How long the program may take to say it is ready, and to answer one step, in seconds (a
  // hung program is an error after this; 0: no limit beyond the caller's `poll`).
  double startSeconds = 30;
  double answerSeconds = 60;
  // -v: what the link does (start, each exchange's size, stop), one line each.
  std::function<void(const std::string&)> log;
};

// Starts the program the .e file names and waits until it is ready. The errors name the .e file:
// a program not found or not executable, one that exits or does not answer before it is ready.
llvm::Expected<std::unique_ptr<EnvironmentLink>> startChildProgram(const CommSpec& spec,
                                                                   const ChildProgramOptions& options = {});

// Where PATH (or a name with a slash) finds `program`; empty if nowhere.
std::string findProgram(const std::string& program);

}  // namespace lcjit::runtime
