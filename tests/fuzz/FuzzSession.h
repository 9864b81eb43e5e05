// The session the model-running targets (pipeline, strb) share: one for the process, under the
// model guard's limits, with its compile cache in the fuzz build.
#pragma once
#include <cstdio>
#include <cstdlib>

#include "app/session/Session.h"
#include "runtime/Engine.h"

namespace lcjit::fuzz {

// Never freed: libFuzzer ends the process without returning.
inline app::Session* guardedSession(const runtime::EngineLimits& limits) {
  auto s = app::Session::create(LCJIT_FUZZ_CACHE_DIR);
  if (!s) {
    std::fprintf(stderr, "%s\n", llvm::toString(s.takeError()).c_str());
    std::abort();
  }
  app::Session* session = s->release();
  session->setLimits(limits);
  return session;
}

}  // namespace lcjit::fuzz
