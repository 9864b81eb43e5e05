// A small environmental program for lcjit's tests: the program side of vlab's protocol (as
// docs/environment.md describes it), written for the tests, over files, memory or pipes as its
// .e file says. Command line, as the simulator builds it:
//
//   envfixture [-k KEY] [-ext EXT] -e FILE.e MODE [ARG]
//
// MODE says how it answers each communication module `ID E(v1,…,vn)` of a step:
//   plus1     E(v1+1,…,vn+1): every value sent, plus one
//   turtle    E(t1,…,tk): the numbers of the module's turtle lines, in the order they came (at
//             most 20), so a test reads back every turtle field through an EA20
//   chunk N   as plus1, in chunks of N answers (`Control: 1`, `0` …, `4`)
//   immediate as plus1, each answer written as soon as its module is read (pipes)
//   crash     abort() when the first step arrives
//   exit      exit(3) when the first step arrives
//   hang      never answer
//   garbage   answer `hello` and a module line without parentheses
//   silent    never say it is ready
// With LCJIT_ENV_FIXTURE_LOG set, it appends `pid KEY` to that file when it starts and `step N`
// for each request.
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/ipc.h>
#include <sys/sem.h>
#include <sys/shm.h>
#include <unistd.h>

namespace {

enum class Transport { Files, Memory, Pipes };

struct Spec {
  Transport transport = Transport::Pipes;
  std::vector<std::string> turtleFormats;  // position, heading, left, up, line width, scale factor
  bool following = false;
};

Spec readSpec(const std::string& path) {
  Spec spec;
  std::ifstream f(path);
  std::string line;
  static const char* kTurtle[] = {"turtle position:", "turtle heading:", "turtle left:",
                                  "turtle up:",       "turtle line width:", "turtle scale factor:"};
  std::string formats[6];
  while (std::getline(f, line)) {
    if (line.rfind("communication type:", 0) == 0) {
      std::string t = line.substr(19);
      spec.transport = t.find("files") != std::string::npos    ? Transport::Files
                       : t.find("memory") != std::string::npos ? Transport::Memory
                                                               : Transport::Pipes;
    }
    if (line.rfind("following module:", 0) == 0)
      spec.following = line.find("on") != std::string::npos || line.find("yes") != std::string::npos;
    for (int i = 0; i < 6; ++i)
      if (line.rfind(kTurtle[i], 0) == 0) formats[i] = line.substr(std::strlen(kTurtle[i]));
  }
  for (auto& fmt : formats)
    if (!fmt.empty()) spec.turtleFormats.push_back(fmt);
  return spec;
}

// The numbers on a turtle line: what follows its format's text before the first '%'.
std::vector<double> numbers(const std::string& line, const std::string& format) {
  size_t skip = format.find('%');
  std::vector<double> out;
  const char* p = line.c_str() + std::min(skip == std::string::npos ? 0 : skip, line.size());
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    double v = std::strtod(p, &end);
    if (end == p) break;
    out.push_back(v);
    p = end;
  }
  return out;
}

struct Channel {
  Transport transport;
  int semId = -1;
  char* shm = nullptr;
  std::string toName, fromName;

  void waitTurn() {
    if (transport == Transport::Pipes) return;
    struct sembuf op {0, -1, 0};
    while (semop(semId, &op, 1) != 0 && errno == EINTR) {
    }
  }
  void giveTurn() {
    if (transport == Transport::Pipes) return;
    struct sembuf op {1, 1, 0};
    semop(semId, &op, 1);
  }
  // The request's lines (files, memory: all of it; pipes: up to its control line).
  std::vector<std::string> request() {
    std::vector<std::string> lines;
    std::string text;
    if (transport == Transport::Files) {
      std::ifstream f(toName);
      std::stringstream ss;
      ss << f.rdbuf();
      text = ss.str();
    } else if (transport == Transport::Memory) {
      text.assign(shm, strnlen(shm, 50000));
    } else {
      char buf[4096];
      while (std::fgets(buf, sizeof buf, stdin)) {
        lines.emplace_back(buf);
        if (lines.back().back() == '\n') lines.back().pop_back();
        if (lines.back().rfind("Control", 0) == 0) break;
      }
      return lines;
    }
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      lines.push_back(line);
      if (line.rfind("Control", 0) == 0) break;
    }
    return lines;
  }
  void answer(const std::string& text) {
    if (transport == Transport::Files) {
      std::ofstream f(fromName, std::ios::trunc);
      f << text;
    } else if (transport == Transport::Memory) {
      std::memcpy(shm + 50000, text.c_str(), std::min<size_t>(text.size() + 1, 10000));
    } else {
      std::fputs(text.c_str(), stdout);
      std::fflush(stdout);
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  int key = 0;
  std::string ext, efile;
  int i = 1;
  for (; i + 1 < argc && argv[i][0] == '-'; i += 2) {
    if (!std::strcmp(argv[i], "-k")) key = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "-ext")) ext = argv[i + 1];
    else if (!std::strcmp(argv[i], "-e")) efile = argv[i + 1];
  }
  std::string mode = i < argc ? argv[i] : "plus1";
  int chunkSize = i + 1 < argc ? std::atoi(argv[i + 1]) : 0;
  Spec spec = readSpec(efile);
  if (const char* log = std::getenv("LCJIT_ENV_FIXTURE_LOG")) {
    std::ofstream(log, std::ios::app) << "pid " << getpid() << " " << key << "\n";
  }
  Channel ch{spec.transport};
  if (mode == "silent") {
    for (;;) pause();
  }
  if (spec.transport != Transport::Pipes) {
    ch.semId = semget(key, 2, 0600);
    if (ch.semId < 0) return 2;
    union {
      int val;
    } zero{0};
    semctl(ch.semId, 1, SETVAL, zero);  // ready
    if (spec.transport == Transport::Memory) {
      int id = shmget(key - 1, 60000, 0600);
      if (id < 0) return 2;
      ch.shm = static_cast<char*>(shmat(id, nullptr, 0));
    } else {
      ch.toName = ".to_field" + ext;
      ch.fromName = ".from_field" + ext;
    }
  } else {
    std::fputc(1, stdout);
    std::fflush(stdout);
  }
  for (int step = 0;; ++step) {
    ch.waitTurn();
    std::vector<std::string> lines = ch.request();
    if (const char* log = std::getenv("LCJIT_ENV_FIXTURE_LOG")) std::ofstream(log, std::ios::app) << "step " << step << "\n";
    bool exitRequested = !lines.empty() && (std::atoi(lines.back().c_str() + 8) & 8);
    if (exitRequested || lines.empty()) {
      ch.answer("Control: 5\n");
      ch.giveTurn();
      return 0;
    }
    if (mode == "crash") std::abort();
    if (mode == "exit") std::exit(3);
    if (mode == "hang") {
      for (;;) pause();
    }
    if (mode == "garbage") {
      ch.answer("hello\n12 E 3\nControl: 5\n");
      ch.giveTurn();
      continue;
    }
    // Modules: an `ID E(...)` line, then one line per configured turtle format.
    std::vector<std::string> answers;
    for (size_t l = 0; l < lines.size() && lines[l].rfind("Control", 0) != 0;) {
      const std::string& head = lines[l++];
      unsigned long id = std::strtoul(head.c_str(), nullptr, 10);
      std::vector<double> values, turtle;
      size_t open = head.find('('), close = head.find(')');
      std::string inside = head.substr(open + 1, close - open - 1);
      for (size_t f = 0;;) {
        size_t comma = inside.find(',', f);
        values.push_back(std::atof(inside.substr(f, comma - f).c_str()));
        if (comma == std::string::npos) break;
        f = comma + 1;
      }
      for (const auto& fmt : spec.turtleFormats) {
        auto n = numbers(l < lines.size() ? lines[l] : "", fmt);
        turtle.insert(turtle.end(), n.begin(), n.end());
        ++l;
      }
      std::string out = std::to_string(id) + " E(";
      const std::vector<double>& src = mode == "turtle" ? turtle : values;
      size_t count = mode == "turtle" ? std::min<size_t>(src.size(), 20) : src.size();
      for (size_t k = 0; k < count; ++k) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%s%g", k ? "," : "", mode == "turtle" ? src[k] : src[k] + 1);
        out += buf;
      }
      out += ")\n";
      if (mode == "immediate") {
        ch.answer(out);
      } else {
        answers.push_back(out);
      }
    }
    // In pieces of `chunk N` answers, or of what fits in the shared memory's 10 000 bytes: all
    // but the last say "not the last", and each waits for the simulator's turn.
    const size_t perChunk = mode == "chunk" && chunkSize > 0 ? size_t(chunkSize) : answers.size() + 1;
    const size_t room = spec.transport == Transport::Memory ? 9900 : SIZE_MAX;
    std::string text;
    size_t inChunk = 0;
    bool first = true;
    for (size_t k = 0; k <= answers.size(); ++k) {
      bool full = k < answers.size() && (inChunk == perChunk || text.size() + answers[k].size() > room);
      if (full && spec.transport != Transport::Pipes) {
        ch.answer(text + "Control: " + std::to_string(first ? 1 : 0) + "\n");
        ch.giveTurn();
        ch.waitTurn();
        text.clear();
        inChunk = 0;
        first = false;
      }
      if (k < answers.size()) {
        text += answers[k];
        ++inChunk;
      }
    }
    ch.answer(text + "Control: " + std::to_string((first ? 1 : 0) | 4) + "\n");
    ch.giveTurn();
  }
}
