// Environmental programs built into lcjit, for users without vlab: used when the program a .e
// file names is not on PATH. They run in-process but read the very text a child program would
// (values with six decimals, turtle lines through their formats), so their answers are those of
// vlab's programs bit for bit. Built in: honda81 (vlab environment manual §3.1.1).
#pragma once
#include <memory>

#include "runtime/environment/ChildProgram.h"

namespace lcjit::runtime {

// The .e file's program: a child process, or, when the named program is not on PATH and lcjit
// has one of that name, the built-in one (said in `options.log`).
llvm::Expected<std::unique_ptr<EnvironmentLink>> startEnvironment(const CommSpec& spec,
                                                                  const ChildProgramOptions& options = {});

// The built-in program called `name` ("honda81"), or an error if there is none.
llvm::Expected<std::unique_ptr<EnvironmentLink>> startBuiltinProgram(const std::string& name, const CommSpec& spec);

// One communication module as vlab's communication library hands it to a program (CSGetData):
// the id, the values (each read with atof and kept as a float; at most 20), and the turtle
// vectors the .e file has formats for (each read with sscanf's %f after the format's text up to
// its first '%'; `count` says how many numbers the format has, at most 3).
struct CommunicationQuery {
  unsigned long id = 0;
  std::vector<float> values;
  struct Vector {
    float v[3] = {0, 0, 0};
    int count = 0;
  } position, heading, left, up, lineWidth, scaleFactor;
};
// Reads a record (`ID E(…)` and its turtle lines); false if it is not one (no id, no `E`).
bool parseQuery(const std::string& record, const CommSpec& spec, CommunicationQuery& out);

}  // namespace lcjit::runtime
