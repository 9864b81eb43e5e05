// The communication specification file (.e, vlab environment manual §2, lpfg manual §5.10): how
// to start an environmental program and what to send it for each communication module (E1, E2,
// EA20). The same file is read twice, by lcjit and by the program (vlab's communication library,
// libs/comm), so this reader takes each command as that library does where the two meanings
// matter (the transport, the turtle lines the program expects), and lpfg's spellings too.
// Pure data: runtime/environment/ starts the program and speaks to it.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>

#include "runtime/files/TextLines.h"
#include "runtime/files/ViewFile.h"  // ViewFileWarning

namespace lcjit::runtime {

struct CommSpec {
  std::string file;        // the .e file as named on the command line
  std::string executable;  // `executable:` (the command line; required)
  int executableLine = 0;
  // `communication type:`. The program's library takes pipes when the line is missing, so lcjit
  // does too (lpfg speaks files whatever the line says, and hangs unless it says files).
  enum class Transport { Files, Memory, Pipes } transport = Transport::Pipes;
  // `turtle position:` … `turtle scale factor:`: the text after the colon, verbatim (a printf
  // format for the three coordinates, or one value for width and scale); empty = not sent. The
  // program skips the characters before the first `%` and reads up to three numbers.
  std::string position, heading, left, up, lineWidth, scaleFactor;
  // `following module: on|yes` — the module after each communication module is sent too.
  bool followingModule = false;
  bool verbose = false;  // `verbose: on|yes`

  // An error about the program this file starts: "FILE: error: message".
  llvm::Error error(const std::string& message) const {
    return textfile::fail(file, 0, message);
  }
};

// Reads `text` (the file's contents). Missing `executable:` and unusable values are errors
// ("file:line:col: error: …"); unknown commands and cpfg-only ones are warnings and skipped.
llvm::Expected<CommSpec> parseCommSpec(std::string_view text, const std::string& fileName,
                                       std::vector<ViewFileWarning>& warnings);
llvm::Expected<CommSpec> loadCommSpec(const std::string& path, std::vector<ViewFileWarning>& warnings);

// The values of a communication record's `(v1,v2,…)`, `inside` being the text between the
// parentheses: each read with atof and kept as a float, as vlab's library and lpfg both read
// them; at most `max`.
std::vector<float> communicationValues(std::string_view inside, size_t max = SIZE_MAX);

// The program's argv as vlab's masters build it: the command line split at blanks, with
// `-e FILE` after the program's name unless the line already names one.
std::vector<std::string> environmentArguments(const CommSpec& spec);

}  // namespace lcjit::runtime
