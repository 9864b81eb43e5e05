// `lcjit sweep` (docs/sweeps.md): parameter studies. A YAML sweep file names a model, values of its
// -D parameters and seeds; lcjit plans their cross product as numbered runs, runs one of them as a
// batch run in a child process (`sweep task`, what the scheduler calls), and merges the runs'
// records into one CSV table. Scheduling is not lcjit's: GNU parallel runs the tasks on one
// machine (or several over SSH), Slurm as a job array whose script lcjit writes.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <llvm/Support/Error.h>

namespace lcjit::app {

// A sweep file as read: paths as written there (relative to `folder`), values as the runs get them.
struct Sweep {
  std::string file;    // the sweep file, absolute
  std::string folder;  // its folder: every run's working folder
  std::string text;    // what the plan records, so that an edited file is noticed
  std::string model;
  std::vector<std::string> files;
  struct Parameter {
    std::string name;
    std::vector<std::string> values;  // the text of -D NAME=VALUE
  };
  std::vector<Parameter> parameters;
  bool seeded = false;  // false: the runs get no --seed
  std::vector<uint64_t> seeds;
  std::vector<std::string> outputs;  // file names in a run's folder: out.str, out.png, out.obj
  std::vector<std::string> options;  // more lcjit options for every run
};

// One run of the plan: the parameters' values in the sweep file's order, and its seed.
struct SweepRun {
  std::string id;  // 000001, 000002 …
  std::vector<std::pair<std::string, std::string>> values;
  std::optional<uint64_t> seed;
};

// A seed as `--seed N` and the sweep file's seeds take it: a whole number from 0 to 2^64 - 1,
// written in decimal digits alone; nothing else (a sign, 0x, a number past 2^64 - 1: none wraps).
std::optional<uint64_t> seedNumber(const std::string& text);
// What a seed must be, for error messages.
extern const char* const kSeedRange;

// Errors name the sweep file, the line and column, and what is wrong.
llvm::Expected<Sweep> readSweep(const std::string& file);

// The cross product: the first parameter varies slowest, the seed fastest.
std::vector<SweepRun> sweepRuns(const Sweep& sweep);

enum class SweepVerb { Plan, Task, Run, Slurm, Collect };

struct SweepCommand {
  SweepVerb verb = SweepVerb::Plan;
  std::string file;     // plan, run, slurm: the sweep file
  std::string dir;      // the plan's folder: --out of plan, run, slurm ("": beside the file), DIR of task, collect
  std::string id;       // task: which run
  int jobs = 1;         // run: GNU parallel's -j
  int chunk = 10;       // slurm: runs per array task
  std::string version;  // lcjit's, for the records and the plan
};

// Does what the command says, with messages on stderr; returns the exit status.
int runSweep(const SweepCommand& command);

}  // namespace lcjit::app
