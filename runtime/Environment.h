// What the derivation engine needs of an environmental program (vlab environment manual §1.4,
// lpfg manual §5.10): at the start of every step, the communication modules' records go out as
// one request and the answers come back. runtime/environment/ implements it with a child process
// speaking vlab's protocol, or with a program built into lcjit.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include <llvm/Support/Error.h>
#include "runtime/files/CommSpec.h"

namespace lcjit::runtime {

class EnvironmentLink {
 public:
  virtual ~EnvironmentLink() = default;
  virtual const CommSpec& spec() const = 0;
  // One environmental step (`step`: the step about to be derived). Each record is the text
  // vlab's programs read for one communication module: `ID E(v,…)` and its turtle lines; the
  // link adds the control lines. The result is the answer records (`ID E(v,…)` lines of every
  // chunk, without control lines). Blocks until the program has answered; calls `poll` every
  // few milliseconds meanwhile, which may throw to abandon the wait (a stop request, a time
  // limit). An error says what the program did wrong, naming the .e file.
  virtual llvm::Expected<std::string> exchange(const std::vector<std::string>& records, int step,
                                               const std::function<void()>& poll) = 0;
};

}  // namespace lcjit::runtime
