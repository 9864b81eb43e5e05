// The record of one batch run (--run-record FILE, docs/sweeps.md): what it was run with (the -D
// overrides, the seed, lcjit's version, its input files' hashes), how it ended, and what it made
// (module counts, the geometry's size, the values the model reported), as one JSON object: a
// row of a sweep's table.
#pragma once

#include <llvm/Support/Error.h>
#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace lcjit::app {

class Session;
struct ModelFiles;
struct PhaseTimes;

// How a run went: `error` empty when it succeeded.
struct RunOutcome {
  std::string error;
  std::optional<uint64_t> seed;  // --seed
};

// What a run was run with, added to `out`: lcjit's version, the model, its input files' BLAKE3,
// the -D overrides and the seed (null without --seed). For --stats and the run record.
void addRunIdentity(nlohmann::ordered_json& out, const ModelFiles& files, Session* session,
                    std::optional<uint64_t> seed);

// Writes `path` (through a temporary file and a rename: a reader never sees half a record).
// `session`: the loaded model, or null when it did not load; measures are taken from its
// string (and an interpretation of it) when the run succeeded.
llvm::Error writeRunRecord(const std::string& path, const ModelFiles& files, Session* session,
                           const RunOutcome& outcome, const PhaseTimes& times);

}  // namespace lcjit::app
