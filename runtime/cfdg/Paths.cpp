// Context Free's paths (Paths.h): the operations on an AGG path_storage, the commands that cover
// them, their bounds through cfdg's AGG pipeline, and the functions compiled path bodies call.
// Sections:
//   1. Measuring a command: cfdg's path iterator (curves flattened, stroked, transformed)
//   2. A run of a path's body: operations, commands, sub-paths
//   3. Finishing and painting a path
//   4. The functions compiled path bodies call (lcjit/cfdg.h)
#include "runtime/cfdg/Paths.h"

#include "runtime/cfdg/Tiling.h"

#include <agg_basics.h>
#include <agg_bounding_rect.h>
#include <agg_conv_curve.h>
#include <agg_conv_stroke.h>
#include <agg_conv_transform.h>
#include <agg_path_storage.h>
#include <agg_trans_affine.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace lcjit::runtime::cfdg {

// ---------------------------------------------------------------------------------------------
// 1. Measuring a command
// ---------------------------------------------------------------------------------------------

// cfdg measures every command (and every primitive, stroked 0.1 wide) with one set of AGG
// converters, kept from one to the next: the curve flattener's angle tolerance is set only for
// strokes, so a fill's curves are flattened with the tolerance the last stroke measured left.
struct PathEngine::Measure {
  using Curved = agg::conv_curve<agg::path_storage>;
  using CurvedStroked = agg::conv_stroke<Curved>;
  using CurvedStrokedTrans = agg::conv_transform<CurvedStroked, const agg::trans_affine>;
  using CurvedTrans = agg::conv_transform<Curved, const agg::trans_affine>;
  using CurvedTransStroked = agg::conv_stroke<CurvedTrans>;

  agg::path_storage none;
  agg::trans_affine unit;
  Curved curved{none};
  CurvedStroked curvedStroked{curved};
  CurvedStrokedTrans curvedStrokedTrans{curvedStroked, unit};
  CurvedTrans curvedTrans{curved, unit};
  CurvedTransStroked curvedTransStroked{curvedTrans};

  // Sets the converters for command `a` through transform `tr`, curves flattened for `accuracy`
  // times the transform's mean scale.
  void apply(agg::path_storage& path, const PathCommandInfo& a, const agg::trans_affine& tr, double accuracy) {
    const double scale = std::sqrt(std::fabs(tr.determinant()));
    curved.attach(path);
    if (a.flags & kFill) {
      curvedTrans.transformer(tr);
      curved.approximation_scale(accuracy * scale);
      return;
    }
    const auto join = agg::line_join_e(a.flags & kJoinMask);
    const auto cap = agg::line_cap_e((a.flags >> kCapShift) & 7);
    if (a.flags & kIsoWidth) {
      curvedTrans.transformer(tr);
      curvedTransStroked.width(a.width * scale);
      curvedTransStroked.line_join(join);
      curvedTransStroked.line_cap(cap);
      curvedTransStroked.miter_limit(a.miterLimit);
      curvedTransStroked.inner_join(agg::inner_round);
      curvedTransStroked.approximation_scale(accuracy);
    } else {
      curvedStrokedTrans.transformer(tr);
      curvedStroked.width(a.width);
      curvedStroked.line_join(join);
      curvedStroked.line_cap(cap);
      curvedStroked.miter_limit(a.miterLimit);
      curvedStroked.inner_join(agg::inner_round);
      curvedStroked.approximation_scale(accuracy * scale);
    }
    curved.approximation_scale(accuracy * scale);
    // Cusps are handled only when the visual width is considerable.
    curved.angle_tolerance(a.width * scale > 1.0 ? 0.2 : 0.0);
  }

  // The box of command `a`'s outline through `tr`, curves flattened for world scale `scale`;
  // invalid when the outline has no vertex.
  Bounds box(agg::path_storage& path, const PathCommandInfo& a, const agg::trans_affine& tr, double scale) {
    apply(path, a, tr, scale * 0.1);
    Bounds b;
    bool any;
    if (a.flags & kFill) any = agg::bounding_rect_single(curvedTrans, a.index, &b.minX, &b.minY, &b.maxX, &b.maxY);
    else if (a.flags & kIsoWidth)
      any = agg::bounding_rect_single(curvedTransStroked, a.index, &b.minX, &b.minY, &b.maxX, &b.maxY);
    else any = agg::bounding_rect_single(curvedStrokedTrans, a.index, &b.minX, &b.minY, &b.maxX, &b.maxY);
    if (!any || !std::isfinite(b.minX) || !std::isfinite(b.minY) || !std::isfinite(b.maxX) || !std::isfinite(b.maxY))
      return {};
    return b;
  }
};

namespace {

agg::trans_affine transformOf(const __cf_State& s) { return {s.sx, s.shy, s.shx, s.sy, s.tx, s.ty}; }

constexpr double kPi = 3.14159265358979323846;

}  // namespace

// ---------------------------------------------------------------------------------------------
// 2. A run of a path's body
// ---------------------------------------------------------------------------------------------

// One run of a path's body: the outline its operations build and what its commands covered. The
// flags are cfdg's renderer's: where the next command's operations start, whether the current
// sub-path is closed and the path ended, whether the next drawing operation needs a move first,
// whether operations wait for a command (else the path ends with an implicit FILL).
struct PathEngine::Run {
  PathEngine& engine;
  agg::path_storage path;
  std::vector<PathCommandInfo> commands;
  double lastX = 0, lastY = 0;
  bool stop = false, closed = false, wantMoveTo = true, wantCommand = true;
  bool opsOnly = false;      // inside a sub-path of operations: no command may run
  bool transformed = false;  // operations are transformed by the frame
  unsigned index = 0, nextIndex = 0;
  // Measuring (no painter): the commands' boxes at this world scale; or painting.
  double scale = 0;
  Bounds bounds;
  const PathPainter* painter = nullptr;
  const std::deque<std::vector<double>>* bound;  // the run's shape values (a sub-path may be one)

  explicit Run(PathEngine& e) : engine(e), bound(e.bound_) {}

  void op(__cf_Ctx* c, int op, int flags, int count, double* d) {
    const agg::trans_affine tr = transformOf(*c->frame);
    double rx = 0, ry = 0, angle = 0;
    bool sweep = (flags & kArcCW) == 0;
    const bool large = (flags & kArcLarge) != 0;
    if (op == __cf_ArcTo || op == __cf_ArcRel) {
      if (count == 5) {  // radii and the ellipse's angle, else a circle's radius
        rx = d[2], ry = d[3];
        angle = d[4] * 0.0174532925199;
      } else {
        rx = ry = d[2];
      }
      if (rx < 0.0 || ry < 0.0) {
        rx = std::fabs(rx), ry = std::fabs(ry);
        sweep = !sweep;
      }
    } else if (transformed) {
      tr.transform(&d[0], &d[1]);
      tr.transform(&d[2], &d[3]);
      tr.transform(&d[4], &d[5]);
    }
    // The first operation after a command starts the operations the next command covers.
    index = nextIndex;
    closed = false;
    stop = false;
    wantCommand = true;

    if (op == __cf_ClosePoly) {
      if (path.total_vertices() > 1 && agg::is_drawing(path.vertices().last_command())) {
        // The sub-path's start: the last point becomes the move that began it.
        const unsigned last = path.total_vertices() - 1;
        unsigned cmd = agg::path_cmd_stop;
        for (unsigned i = last - 1; i < last && agg::is_vertex(cmd = path.command(i)); --i)
          if (agg::is_move_to(cmd)) {
            path.vertex(i, &lastX, &lastY);
            break;
          }
        if (!agg::is_move_to(cmd)) __cf_fail(c, "CLOSEPOLY: Unable to find a MOVETO/MOVEREL for start of path.");
        if (flags & kAlign) path.modify_vertex(last, lastX, lastY);
      } else if (flags & kAlign) {
        __cf_fail(c, "CLOSEPOLY: Nothing to align to.");
      }
      path.close_polygon();
      closed = true;
      wantMoveTo = true;
      return;
    }

    // A drawing operation after a close (or first) starts from the last point.
    if (wantMoveTo && op > __cf_MoveRel) {
      wantMoveTo = false;
      path.move_to(lastX, lastY);
    }
    switch (op) {
      case __cf_MoveRel: path.rel_to_abs(&d[0], &d[1]); [[fallthrough]];
      case __cf_MoveTo:
        path.move_to(d[0], d[1]);
        wantMoveTo = false;
        break;
      case __cf_LineRel: path.rel_to_abs(&d[0], &d[1]); [[fallthrough]];
      case __cf_LineTo: path.line_to(d[0], d[1]); break;
      case __cf_ArcRel: path.rel_to_abs(&d[0], &d[1]); [[fallthrough]];
      case __cf_ArcTo: {
        if (!agg::is_vertex(path.last_vertex(&d[2], &d[3])) || (transformed && tr.determinant() < 1e-10)) break;
        if (transformed) {
          // AGG's arc is made untransformed, from the start point taken back, then its curves are
          // transformed and the start point restored.
          const unsigned start = path.total_vertices() - 1;
          path.transform(~tr, start);
          path.arc_to(rx, ry, angle, large, sweep, d[0], d[1]);
          path.modify_vertex(start, d[2], d[3]);
          path.transform(tr, start + 1);
        } else {
          path.arc_to(rx, ry, angle, large, sweep, d[0], d[1]);
        }
        break;
      }
      case __cf_CurveRel:
        path.rel_to_abs(&d[0], &d[1]);
        path.rel_to_abs(&d[2], &d[3]);
        path.rel_to_abs(&d[4], &d[5]);
        [[fallthrough]];
      case __cf_CurveTo:
        if ((flags & kContinuous) && !agg::is_curve(path.last_vertex(&d[4], &d[5])))
          __cf_fail(c, "Smooth curve operations must be preceded by another curve operation.");
        if (count == 2) path.curve3(d[0], d[1]);
        else if (count == 4 && (flags & kContinuous)) path.curve4(d[2], d[3], d[0], d[1]);
        else if (count == 4) path.curve3(d[2], d[3], d[0], d[1]);
        else if (count == 6) path.curve4(d[2], d[3], d[4], d[5], d[0], d[1]);
        break;
      default: break;
    }
    path.last_vertex(&lastX, &lastY);
  }

  // Ends the current sub-path and the path (a command, or the body's end); with `setAttr`,
  // whether operations are left without a command (they get the implicit FILL).
  bool finish(bool setAttr) {
    if (!closed) {
      path.end_poly(0);
      closed = true;
    }
    if (!stop) {
      path.start_new_path();
      stop = true;
    }
    wantMoveTo = true;
    nextIndex = path.total_vertices();
    if (setAttr && wantCommand) {
      wantCommand = false;
      return true;
    }
    return false;
  }

  void command(__cf_Ctx* c, const __cf_State& s, int flags, double width) {
    if (opsOnly) __cf_fail(c, "Path commands not allowed at this point");
    if (path.total_vertices() == 0) __cf_fail(c, "Path commands must be preceded by at least one path operation");
    wantCommand = false;
    finish(false);
    // The covered sub-paths' last points snap to their first (unless the previous command, over
    // the same operations, did it).
    if (commands.empty() || commands.back().index != index)
      for (unsigned i = index; i < path.total_vertices(); i = path.align_path(i)) {
      }
    PathCommandInfo info;
    info.index = index;
    info.flags = flags | s.blend;
    info.width = width;
    commands.push_back(info);
    if (painter) {
      std::vector<PathVertex> outline;
      for (unsigned i = info.index; i < path.total_vertices(); ++i) {
        PathVertex v;
        v.command = path.vertex(i, &v.x, &v.y);
        if (agg::is_stop(v.command)) break;
        outline.push_back(v);
      }
      (*painter)(outline, info, s);
    } else {
      bounds.merge(engine.measure_->box(path, info, transformOf(s), scale));
    }
  }

  // A primitive as a sub-path: cfdg's operations for it (a circle is two arcs).
  void primitive(__cf_Ctx* c, int shape) {
    auto go = [&](int o, double x, double y, double r = 0) {
      double d[6] = {x, y, r, 0, 0, 0};
      op(c, o, 0, 0, d);
    };
    if (shape == 0) {
      go(__cf_MoveTo, 0.5, 0), go(__cf_ArcTo, -0.5, 0, 0.5), go(__cf_ArcTo, 0.5, 0, 0.5);
    } else if (shape == 1) {
      go(__cf_MoveTo, 0.5, 0.5), go(__cf_LineTo, -0.5, 0.5), go(__cf_LineTo, -0.5, -0.5), go(__cf_LineTo, 0.5, -0.5);
    } else {
      const double h = 0.5 / std::cos(kPi / 6.0);
      go(__cf_MoveTo, 0, h), go(__cf_LineTo, -0.5, -h / 2.0), go(__cf_LineTo, 0.5, -h / 2.0);
    }
    go(__cf_ClosePoly, 0, 0);
  }

  // Runs path `shape`'s body (from the path shape or a sub-path element) with state `s`.
  void body(__cf_Ctx* c, int shape, const __cf_State& s, const double* params) {
    const __cf_State* frame = c->frame;
    c->frame = &s;
    engine.design_.rules[engine.firstRule_[size_t(shape)]].body(c, params);
    c->frame = frame;
  }

  // A sub-path element: path `shape`'s body (or a primitive's operations) in this run, with the
  // element's state; `body` is what the element expects the path to hold.
  void subpath(__cf_Ctx* c, int shape, const __cf_State& s, const double* params, int body) {
    const __cf_Design& d = engine.design_;
    const bool path = shape >= 4 && shape < d.shapeCount && d.shapes[shape].isPath;
    const bool primitive = !path && shape >= 0 && shape < 3 && body == __cf_PathOps;
    if (!primitive && (!path || d.shapes[shape].pathBody != body))
      __cf_fail(c, "Subpath is not of the expected type (path ops/commands)");
    const bool outerOpsOnly = opsOnly;
    opsOnly = opsOnly || body == __cf_PathOps;
    if (primitive) {
      const __cf_State* frame = c->frame;
      c->frame = &s;
      this->primitive(c, shape);
      c->frame = frame;
    } else {
      this->body(c, shape, s, params);
    }
    opsOnly = outerOpsOnly;
  }
  // A sub-path element naming a shape value (a parameter or variable of type shape).
  void subpath(__cf_Ctx* c, double value, const __cf_State& s, int body) {
    static const std::deque<std::vector<double>> none;
    const ShapeValue v = shapeValue(engine.design_, bound ? *bound : none, value);
    if (v.shape < 0) __cf_fail(c, "a shape value that is no shape");
    subpath(c, v.shape, s, v.params, body);
  }

  // The whole body of path `shape`, then the implicit FILL if operations are left uncovered.
  void run(__cf_Ctx* c, int shape, const __cf_State& s, const double* params) {
    void* outer = c->path;
    c->path = this;
    body(c, shape, s, params);
    if (finish(true)) {
      // A command of Context Free's own, not from the design: its seed is the seed constant.
      c->cur ^= kSeedBase;
      c->cur = stepSeed(c->cur);
      command(c, s, kFill, 0.1);
    }
    c->path = outer;
  }
};

// ---------------------------------------------------------------------------------------------
// 3. Finishing and painting a path
// ---------------------------------------------------------------------------------------------

PathEngine::PathEngine(const __cf_Design& design, const std::deque<std::vector<double>>* bound)
    : design_(design), bound_(bound), firstRule_(size_t(design.shapeCount), -1), measure_(std::make_unique<Measure>()) {
  for (int r = design.ruleCount - 1; r >= 0; --r) firstRule_[size_t(design.rules[r].shape)] = r;
}

PathEngine::~PathEngine() = default;

Bounds PathEngine::measure(__cf_Ctx* c, int shape, const __cf_State& s, const double* params, uint64_t seed,
                           double scale, double& area) {
  Run run(*this);
  run.scale = scale;
  c->cur = seed;  // no rule is chosen: the body runs from the path's seed
  run.run(c, shape, s, params);
  const Bounds& b = run.bounds;
  area = b.valid() ? std::fabs((b.maxX - b.minX) * (b.maxY - b.minY)) : 0.0;
  return b;
}

void PathEngine::primitiveMeasured(double determinant) {
  measure_->curved.angle_tolerance(0.1 * std::sqrt(std::fabs(determinant)) > 1.0 ? 0.2 : 0.0);
}

void PathEngine::paint(const FinishedPath& p, const Expansion& e, const PathPainter& painter) {
  Run run(*this);
  run.painter = &painter;
  run.bound = &e.bound;
  __cf_Ctx ctx{};
  ctx.cur = p.seed;
  ctx.statics = e.statics.data();
  ctx.time[0] = e.frameTime;
  ctx.time[1] = e.frame;
  run.run(&ctx, p.shape, p.state, p.params.get());
}

std::string PathEngine::svg(const FinishedPath& p, const Expansion& e, const Framing& f,
                            const std::vector<std::pair<double, double>>& copies, const Affine& toSvg, int& nextId,
                            int& precision) {
  std::string out;
  int lastId = 0;
  unsigned lastIndex = ~0u;
  paint(p, e, [&](const std::vector<PathVertex>& outline, const PathCommandInfo& info, const __cf_State& s) {
    // Each command once per copy of a tiled picture (Tiling.h), all copies before the next command.
    forEachCopy(Affine{s.sx, s.shy, s.shx, s.sy, s.tx, s.ty}, copies, f, toSvg, [&](const Affine& m) {
      double rgba[4];
      rgbOf(s.colour, rgba);
      auto byte = [](double v) { return unsigned(v * 255.0 + 0.5); };
      char b[512];
      const bool fill = info.flags & kFill, iso = info.flags & kIsoWidth;
      std::snprintf(b, sizeof b, "  <g %s=\"#%02x%02x%02x\"", fill ? "stroke=\"none\" fill" : "fill=\"none\" stroke",
                    byte(rgba[0]), byte(rgba[1]), byte(rgba[2]));
      out += b;
      if (byte(rgba[3]) != 255) {
        std::snprintf(b, sizeof b, " %s-opacity=\"%.*g\"", fill ? "fill" : "stroke", precision, byte(rgba[3]) / 255.0);
        out += b;
      }
      if (fill) {
        out += info.flags & kEvenOdd ? " fill-rule=\"evenodd\"" : " fill-rule=\"nonzero\"";
      } else {
        // Context Free's names, its flag bits included (an explicit cap or join reads "miter").
        const int cap = (info.flags >> kCapShift) & 15, join = info.flags & 15;
        std::snprintf(b, sizeof b,
                      "\n     stroke-width=\"%.*g\" stroke-linecap=\"%s\" stroke-linejoin=\"%s\" stroke-miterlimit=\"%.*g\"",
                      precision, iso ? info.width * std::sqrt(std::fabs(m.determinant())) : info.width,
                      cap == 1 ? "butt" : cap == 2 ? "circle" : "miter", join == 3 ? "bevel" : join == 2 ? "round" : "miter",
                      precision, info.miterLimit);
        out += b;
      }
      if (iso) {
        out += " >\n";  // an iso-width outline is written in pixels
      } else {
        std::snprintf(b, sizeof b, "\n     transform=\"matrix(%.8g %.8g %.8g %.8g %.8g %.8g)\">\n", m.sx, m.shy, m.shx, m.sy,
                      m.tx, m.ty);
        out += b;
        precision = 8;
      }
      if (info.index == lastIndex && !iso) {
        std::snprintf(b, sizeof b, "    <use xlink:href=\"#path%d\" />\n  </g>\n", lastId);
        out += b;
        return;
      }
      lastIndex = info.index, lastId = nextId++;
      std::snprintf(b, sizeof b, "    <path id=\"path%d\" d=\"", lastId);
      out += b;
      const char* sep = "";
      for (size_t i = 0; i < outline.size(); ++i) {
        unsigned cmd = outline[i].command;
        const char* letter = nullptr;
        int points = 1;
        switch (cmd & agg::path_cmd_mask) {
          case agg::path_cmd_move_to: letter = "M"; break;
          case agg::path_cmd_line_to: letter = "L"; break;
          case agg::path_cmd_curve3: letter = "Q", points = 2; break;
          case agg::path_cmd_curve4: letter = "C", points = 3; break;
          case agg::path_cmd_end_poly:
            if (cmd & agg::path_flags_close) out += std::string(sep) + "Z", sep = " ";
            continue;
          default: continue;
        }
        out += std::string(sep) + letter;
        for (int k = 0; k < points && i < outline.size(); ++k, ++i) {
          double x = outline[i].x, y = outline[i].y;
          if (iso) m.apply(x, y);
          std::snprintf(b, sizeof b, " %.*g,%.*g", precision, x, precision, y);
          out += b;
        }
        --i;
        sep = " ";
      }
      out += "\"/>\n  </g>\n";
    });
  });
  return out;
}

}  // namespace lcjit::runtime::cfdg

// ---------------------------------------------------------------------------------------------
// 4. The functions compiled path bodies call
// ---------------------------------------------------------------------------------------------
using lcjit::runtime::cfdg::PathEngine;

namespace {
PathEngine::Run& runOf(__cf_Ctx* c) {
  if (!c->path) __cf_fail(c, "a path operation or command outside a path");
  return *static_cast<PathEngine::Run*>(c->path);
}
}  // namespace

extern "C" {

void __cf_pathOp(__cf_Ctx* c, int op, int flags, int count, double* data) { runOf(c).op(c, op, flags, count, data); }

void __cf_pathCommand(__cf_Ctx* c, const __cf_State* s, int flags, double width) {
  runOf(c).command(c, *s, flags, width);
}

int __cf_pathEnterOps(__cf_Ctx* c, __cf_State* frame) {
  PathEngine::Run& r = runOf(c);
  const int saved = r.transformed;
  if (!r.transformed) {
    frame->sx = frame->sy = 1;
    frame->shy = frame->shx = frame->tx = frame->ty = 0;
  }
  r.transformed = true;
  return saved;
}

void __cf_pathLeaveOps(__cf_Ctx* c, int saved) { runOf(c).transformed = saved != 0; }

void __cf_subpath(__cf_Ctx* c, int shape, const __cf_State* s, const double* params, int body) {
  runOf(c).subpath(c, shape, *s, params, body);
}

void __cf_subpath_value(__cf_Ctx* c, double value, const __cf_State* s, int body) {
  runOf(c).subpath(c, value, *s, body);
}

}  // extern "C"

namespace lcjit::runtime::cfdg {
std::vector<std::pair<std::string, void*>> pathHostSymbols() {
  return {
      {"__cf_pathOp", reinterpret_cast<void*>(&__cf_pathOp)},
      {"__cf_pathCommand", reinterpret_cast<void*>(&__cf_pathCommand)},
      {"__cf_pathEnterOps", reinterpret_cast<void*>(&__cf_pathEnterOps)},
      {"__cf_pathLeaveOps", reinterpret_cast<void*>(&__cf_pathLeaveOps)},
      {"__cf_subpath", reinterpret_cast<void*>(&__cf_subpath)},
      {"__cf_subpath_value", reinterpret_cast<void*>(&__cf_subpath_value)},
  };
}
}  // namespace lcjit::runtime::cfdg
