// The .e reader. Commands are matched as vlab's communication library matches them: the text up
// to the first colon (or tab) at the start of the line, exactly. The program reads this file
// itself, so a command it would not see (one indented, say) is reported rather than guessed at.
#include "runtime/files/CommSpec.h"

#include <cstdlib>
#include <cstring>
#include <optional>

#include <llvm/Support/MemoryBuffer.h>
#include "runtime/files/TextLines.h"

namespace lcjit::runtime {

namespace {

using namespace textfile;

// A turtle line's format gets three doubles: only floating-point conversions (at most three, as
// the program reads at most three numbers) and %% are safe. Returns the offset of a bad '%'.
std::optional<size_t> badFormat(std::string_view f) {
  int conversions = 0;
  for (size_t i = 0; i < f.size(); ++i) {
    if (f[i] != '%') continue;
    const size_t at = i++;
    if (i < f.size() && f[i] == '%') continue;
    while (i < f.size() && std::strchr("-+ #0", f[i])) ++i;
    while (i < f.size() && std::isdigit((unsigned char)f[i])) ++i;
    if (i < f.size() && f[i] == '.')
      for (++i; i < f.size() && std::isdigit((unsigned char)f[i]);) ++i;
    if (i < f.size() && f[i] == 'l') ++i;
    if (i >= f.size() || !std::strchr("fFeEgGaA", f[i]) || ++conversions > 3) return at;
  }
  return std::nullopt;
}

}  // namespace

llvm::Expected<CommSpec> parseCommSpec(std::string_view text, const std::string& fileName,
                                       std::vector<ViewFileWarning>& warnings) {
  CommSpec spec;
  spec.file = fileName;
  auto warn = [&](size_t line, size_t column, std::string message) {
    warnings.push_back({fileName, int(line), int(column), std::move(message)});
  };
  const auto lines = splitLines(text);
  for (size_t n = 0; n < lines.size(); ++n) {
    const std::string_view line = lines[n];
    const size_t ln = n + 1;
    if (trim(line).empty() || line[0] == '#') continue;  // blank; lpfg takes '#' lines for cpp's markers
    size_t colon = line.find_first_of(":\t");
    if (line[0] == ' ' || line[0] == '\t') {
      warn(ln, 1, "a command must start the line (the environmental program would not see it): line ignored");
      continue;
    }
    if (colon == std::string_view::npos || line[colon] != ':') {
      warn(ln, 1, "not a command ('keyword: value'): line ignored");
      continue;
    }
    const std::string_view key = line.substr(0, colon);
    const std::string_view rest = line.substr(colon + 1);  // verbatim: a turtle format keeps its blanks
    const size_t restColumn = colon + 2;
    const std::string_view value = trim(rest);
    const size_t lead = rest.find_first_not_of(" \t");
    const size_t valueColumn = restColumn + (lead == std::string_view::npos ? 0 : lead);
    auto flag = [&](bool& out) {
      if (value == "on" || value == "yes") {
        out = true;
      } else if (value == "off" || value == "no") {
        out = false;
      } else {
        warn(ln, valueColumn, "expected on or off (yes or no), not '" + std::string(value) + "': line ignored");
      }
    };
    if (key == "executable") {
      if (value.empty()) return failAt(fileName, ln, restColumn, "'executable:' names no program");
      spec.executable = std::string(value);
      spec.executableLine = int(ln);
    } else if (key == "communication type") {
      auto w = words(value);
      std::string_view type = w.empty() ? std::string_view() : w[0];
      if (type == "files") {
        spec.transport = CommSpec::Transport::Files;
      } else if (type == "memory") {
        spec.transport = CommSpec::Transport::Memory;
      } else if (type == "pipes") {
        spec.transport = CommSpec::Transport::Pipes;
      } else if (type == "sockets") {
        return failAt(fileName, ln, valueColumn,
                       "communication type 'sockets' (distributed environments) is not supported: use files, "
                       "memory or pipes");
      } else {
        return failAt(fileName, ln, valueColumn,
                       "unknown communication type '" + std::string(type) + "' (expected files, memory or pipes)");
      }
    } else if (key.substr(0, 7) == "turtle ") {
      std::string* format = key == "turtle position"       ? &spec.position
                            : key == "turtle heading"      ? &spec.heading
                            : key == "turtle left"         ? &spec.left
                            : key == "turtle up"           ? &spec.up
                            : key == "turtle line width"   ? &spec.lineWidth
                            : key == "turtle scale factor" ? &spec.scaleFactor
                                                           : nullptr;
      if (!format) {
        warn(ln, 1, "unknown command '" + std::string(key) + ":': line ignored");
        continue;
      }
      if (auto bad = badFormat(rest))
        return failAt(fileName, ln, restColumn + *bad,
                       "a turtle format takes up to three numbers: %f, %g, %e (with a width or precision) or %%");
      *format = std::string(rest);
    } else if (key == "following module") {
      flag(spec.followingModule);
    } else if (key == "verbose") {
      flag(spec.verbose);
    } else if (key == "interpreted modules" || key == "when interpret" || key == "remote host") {
      warn(ln, 1, "'" + std::string(key) + ":' is cpfg's (lpfg ignores it too): line ignored");
    } else if (key == "strings only" || key == "binary data") {
      if (value != "off" && value != "no")
        return failAt(fileName, ln, 1, "'" + std::string(key) + ":' (cpfg's free-text exchange) is not supported");
    } else {
      warn(ln, 1, "unknown command '" + std::string(key) + ":': line ignored");
    }
  }
  if (spec.executable.empty())
    return failAt(fileName, lines.empty() ? 1 : lines.size(), 1,
                   "no 'executable:' line (the command that starts the environmental program)");
  return spec;
}

llvm::Expected<CommSpec> loadCommSpec(const std::string& path, std::vector<ViewFileWarning>& warnings) {
  auto buf = textfile::readFile(path);
  if (!buf) return buf.takeError();
  return parseCommSpec((*buf)->getBuffer(), path, warnings);
}

std::vector<float> communicationValues(std::string_view inside, size_t max) {
  std::vector<float> values;
  for (size_t f = 0; values.size() < max;) {
    size_t comma = inside.find(',', f);
    values.push_back(float(std::atof(std::string(inside.substr(f, comma == std::string_view::npos ? std::string_view::npos : comma - f)).c_str())));
    if (comma == std::string_view::npos) break;
    f = comma + 1;
  }
  return values;
}

std::vector<std::string> environmentArguments(const CommSpec& spec) {
  std::vector<std::string> argv;
  for (std::string_view w : words(spec.executable)) argv.emplace_back(w);
  bool namesFile = false;
  for (size_t i = 1; i < argv.size(); ++i) namesFile = namesFile || argv[i] == "-e";
  if (!namesFile && !argv.empty()) argv.insert(argv.begin() + 1, {"-e", spec.file});
  return argv;
}

}  // namespace lcjit::runtime
