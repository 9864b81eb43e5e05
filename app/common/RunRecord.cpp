// The record of one batch run (RunRecord.h).
#include "app/common/RunRecord.h"

#include "app/session/Session.h"
#include "support/CacheFiles.h"
#include "runtime/Engine.h"
#include "support/InputFile.h"
#include "runtime/turtle/Drawing.h"

#include <llvm/ADT/StringExtras.h>
#include <llvm/Support/BLAKE3.h>
#include <llvm/Support/MemoryBuffer.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <map>

namespace lcjit::app {

namespace {

using Json = nlohmann::ordered_json;

// Milliseconds to the microsecond, as --stats gives them.
double ms(double v) { return std::round(v * 1000) / 1000; }

// What the string is and what it draws. Module counts by name; of one interpretation (view 0):
// the segments (lines and cylinders), the triangles (polygons and surfaces), the segments'
// total length and the triangles' total area, and the bounding box of everything drawn.
Json measures(runtime::Engine& engine) {
  Json m;
  std::map<std::string, uint64_t> counts;
  const runtime::ModuleTable& modules = engine.modules();
  const runtime::ModuleBuffer& s = engine.string();
  for (size_t p = 0; p < s.size(); p = modules.next(s.data(), p))
    ++counts[modules.info(runtime::ModuleTable::idAt(s.data() + p)).name];
  m["modules"] = counts;
  runtime::Geometry g;
  if (auto e = engine.interpret(g)) {
    m["interpretation_error"] = llvm::toString(std::move(e));
  } else {
    double length = 0, area = 0;
    for (const runtime::Segment& seg : g.segments) length += (seg.to - seg.from).Length();
    for (size_t i = 0; i + 2 < g.indices.size(); i += 3) {
      V3f a = g.vertices[g.indices[i]].position, b = g.vertices[g.indices[i + 1]].position,
                   c = g.vertices[g.indices[i + 2]].position;
      area += 0.5 * ((b - a) % (c - a)).Length();
    }
    m["segments"] = g.segments.size();
    m["triangles"] = g.triangleCount();
    m["length"] = length;
    m["area"] = area;
    runtime::Bounds b = g.bounds();
    if (!b.empty()) m["bbox"] = {b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z};
  }
  m["reported"] = engine.reported();
  return m;
}

std::string blake3Of(const std::string& path) {
  auto file = support::readInputFile(path, /*nullTerminated=*/false);
  if (!file) return "";
  auto bytes = llvm::arrayRefFromStringRef((*file)->getBuffer());
  return llvm::toHex(llvm::BLAKE3::hash<32>(bytes), /*LowerCase=*/true);
}

}  // namespace

void addRunIdentity(Json& r, const ModelFiles& files, Session* session, std::optional<uint64_t> seed) {
  r["lcjit"] = LCJIT_VERSION;
  r["model"] = files.lsystem;
  Json inputs = Json::object();
  const runtime::DrawingFiles none;
  for (const std::string& f : watchedFiles(files, session && session->loaded() ? session->drawing() : none))
    inputs[f] = blake3Of(f);
  r["inputs"] = inputs;
  Json overrides = Json::object();
  for (const auto& [name, value] : files.overrides) overrides[name] = value;
  r["overrides"] = overrides;
  r["seed"] = seed ? Json(*seed) : Json(nullptr);
}

llvm::Error writeRunRecord(const std::string& path, const ModelFiles& files, Session* session,
                           const RunOutcome& outcome, const PhaseTimes& times) {
  Json r;
  addRunIdentity(r, files, session, outcome.seed);
  r["status"] = outcome.error.empty() ? "ok" : "error";
  if (!outcome.error.empty()) r["error"] = outcome.error;
  const bool ran = session && session->loaded();
  r["steps"] = ran ? session->engine().stepsDone() : 0;
  if (ran && outcome.error.empty()) r["measures"] = measures(session->engine());
  r["times_ms"] = {{"preprocess", ms(times.preprocessMs)}, {"rewrite", ms(times.rewriteMs)},
                   {"compile", ms(times.compileMs)},       {"derive", ms(times.deriveMs)},
                   {"interpret", ms(times.interpretMs)},   {"render", ms(times.renderMs)}};
  if (!support::writeCacheFile(path, r.dump(2) + "\n"))
    return llvm::createStringError(path + ": error: cannot write the run record");
  return llvm::Error::success();
}

}  // namespace lcjit::app
