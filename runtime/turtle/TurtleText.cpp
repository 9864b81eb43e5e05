// lpfg's `-dtf` text: one line per turtle command as lpfg's text-file turtle writes it (names,
// `%f` numbers, ", " between arguments; SB/EB, CircleB/CircleFrontB, SetCoordinateSystem and
// user modules are not written; some commands also write the command they are made of, e.g.
// G(d) then F(d), Circle0 then Circle(width/2), LineTo then F(length)). Names and cascades were
// read from lpfg's TextFileTurtle.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "runtime/turtle/Turtle.h"

namespace lcjit::runtime {
namespace {

template <class T> T param(const char* rec, size_t offset) {
  T v;
  std::memcpy(&v, rec + offset, sizeof v);
  return v;
}

struct Line {
  std::string& out;
  void name(const char* n) { out += n; }
  template <class... A> void call(const char* n, A... args) {
    out += n;
    out += '(';
    bool first = true;
    ((append(args, first)), ...);
    out += ')';
  }
  // printf's %f (std::to_chars with a precision rounds as printf does), without printf's
  // arbitrary-precision arithmetic, where most of -dtf's time went. The largest float takes 46
  // characters.
  void append(float v, bool& first) {
    sep(first);
    char b[64];
    out.append(b, std::to_chars(b, b + sizeof b, (double)v, std::chars_format::fixed, 6).ptr);
  }
  void append(int v, bool& first) {
    sep(first);
    out += std::to_string(v);
  }
  void append(const char* s, bool& first) { sep(first); out += s ? s : ""; }
  void sep(bool& first) {
    if (!first) out += ", ";
    first = false;
  }
  void end() { out += '\n'; }
};

V3f vec(const char* rec, size_t off, int kind) {
  switch (kind) {
    case 0: { V2f v = param<V2f>(rec, off); return V3f(v.x, v.y, 0); }
    case 1: { V2d v = param<V2d>(rec, off); return V3f((float)v.x, (float)v.y, 0); }
    case 2: return param<V3f>(rec, off);
    default: { V3d v = param<V3d>(rec, off); return V3f((float)v.x, (float)v.y, (float)v.z); }
  }
}

}  // namespace

void describeTurtleCommand(std::string& out, const char* rec, const V3f& positionBefore, float widthBefore,
                           const V3f& positionAfter) {
  Line l{out};
  __lc_ModuleId id = ModuleTable::idAt(rec);
  auto fp = [&](size_t off) { return param<float>(rec, off); };
  auto ip = [&](size_t off) { return param<int>(rec, off); };
  auto three = [&](const char* n, V3f v) { l.call(n, v.x, v.y, v.z); };
  auto lineThenF = [&](const char* n, V3f v) {
    three(n, v);
    l.end();
    float moved = (positionAfter - positionBefore).Length();
    if (moved >= 1e-5f) l.call("F", moved), l.end();
  };
#define OFF(M, P) offsetof(__lc_R_##M, P)
  switch (id) {
    case __lc_id_F: l.call("F", fp(OFF(F, p0))); break;
    case __lc_id_f: l.call("f", fp(OFF(f, p0))); break;
    case __lc_id_G: l.call("G", fp(OFF(G, p0))), l.end(), l.call("F", fp(OFF(G, p0))); break;
    case __lc_id_g: l.call("g", fp(OFF(g, p0))), l.end(), l.call("f", fp(OFF(g, p0))); break;
    case __lc_id_Left: l.call("Left", fp(OFF(Left, p0))); break;
    case __lc_id_Right: l.call("Right", fp(OFF(Right, p0))); break;
    case __lc_id_Up: l.call("Up", fp(OFF(Up, p0))); break;
    case __lc_id_Down: l.call("Down", fp(OFF(Down, p0))); break;
    case __lc_id_RollL: l.call("RollL", fp(OFF(RollL, p0))); break;
    case __lc_id_RollR: l.call("RollR", fp(OFF(RollR, p0))); break;
    case __lc_id_TurnAround: l.name("TurnAround"); break;
    case __lc_id_IncColor: l.name("IncColor"); break;
    case __lc_id_DecColor: l.name("DecColor"); break;
    case __lc_id_SetColor: l.call("SetColor", ip(OFF(SetColor, p0))); break;
    case __lc_id_SetWidth: l.call("SetWidth", fp(OFF(SetWidth, p0))); break;
    case __lc_id_Label: l.call("Label", param<const char*>(rec, OFF(Label, p0))); break;
    case __lc_id_Circle: l.call("Circle", fp(OFF(Circle, p0))); break;
    case __lc_id_Circle0: l.name("Circle0"), l.end(), l.call("Circle", widthBefore / 2); break;
    case __lc_id_CircleFront: l.call("CircleFront", fp(OFF(CircleFront, p0))); break;
    case __lc_id_CircleFront0: l.name("CircleFront0"), l.end(), l.call("CircleFront", widthBefore / 2); break;
    case __lc_id_Sphere: l.call("Sphere", fp(OFF(Sphere, p0))); break;
    case __lc_id_Sphere0: l.name("Sphere0"), l.end(), l.call("Sphere", widthBefore / 2); break;
    case __lc_id_MoveTo: three("MoveTo", V3f(fp(OFF(MoveTo, p0)), fp(OFF(MoveTo, p1)), fp(OFF(MoveTo, p2)))); break;
    case __lc_id_MoveTo2f: three("MoveTo", vec(rec, OFF(MoveTo2f, p0), 0)); break;
    case __lc_id_MoveTo2d: three("MoveTo", vec(rec, OFF(MoveTo2d, p0), 1)); break;
    case __lc_id_MoveTo3f: three("MoveTo", vec(rec, OFF(MoveTo3f, p0), 2)); break;
    case __lc_id_MoveTo3d: three("MoveTo", vec(rec, OFF(MoveTo3d, p0), 3)); break;
    case __lc_id_MoveRel2f: three("MoveRel", vec(rec, OFF(MoveRel2f, p0), 0)); break;
    case __lc_id_MoveRel2d: three("MoveRel", vec(rec, OFF(MoveRel2d, p0), 1)); break;
    case __lc_id_MoveRel3f: three("MoveRel", vec(rec, OFF(MoveRel3f, p0), 2)); break;
    case __lc_id_MoveRel3d: three("MoveRel", vec(rec, OFF(MoveRel3d, p0), 3)); break;
    case __lc_id_LineTo: lineThenF("LineTo", V3f(fp(OFF(LineTo, p0)), fp(OFF(LineTo, p1)), fp(OFF(LineTo, p2)))); return;
    case __lc_id_LineTo2f: lineThenF("LineTo", vec(rec, OFF(LineTo2f, p0), 0)); return;
    case __lc_id_LineTo2d: lineThenF("LineTo", vec(rec, OFF(LineTo2d, p0), 1)); return;
    case __lc_id_LineTo3f: lineThenF("LineTo", vec(rec, OFF(LineTo3f, p0), 2)); return;
    case __lc_id_LineTo3d: lineThenF("LineTo", vec(rec, OFF(LineTo3d, p0), 3)); return;
    case __lc_id_LineRel2f: lineThenF("LineRel", vec(rec, OFF(LineRel2f, p0), 0)); return;
    case __lc_id_LineRel2d: lineThenF("LineRel", vec(rec, OFF(LineRel2d, p0), 1)); return;
    case __lc_id_LineRel3f: lineThenF("LineRel", vec(rec, OFF(LineRel3f, p0), 2)); return;
    case __lc_id_LineRel3d: lineThenF("LineRel", vec(rec, OFF(LineRel3d, p0), 3)); return;
    case __lc_id_Line2f:
    case __lc_id_Line2d:
    case __lc_id_Line3f:
    case __lc_id_Line3d: {
      int kind = id == __lc_id_Line2f ? 0 : id == __lc_id_Line2d ? 1 : id == __lc_id_Line3f ? 2 : 3;
      size_t size = kind == 0 ? sizeof(V2f) : kind == 1 ? sizeof(V2d) : kind == 2 ? sizeof(V3f) : sizeof(V3d);
      size_t at = OFF(Line2f, p0);
      if (kind == 1) at = OFF(Line2d, p0);
      if (kind == 2) at = OFF(Line3f, p0);
      if (kind == 3) at = OFF(Line3d, p0);
      V3f a = vec(rec, at, kind), b = vec(rec, at + size, kind);
      l.call("Line", a.x, a.y, a.z, b.x, b.y, b.z);
      l.end();
      // The F of the line runs from p1 to p2.
      V3f d = b - a;
      if (d.Length() >= 1e-5f) l.call("F", d.Length()), l.end();
      return;
    }
    case __lc_id_SetHead:
      l.call("SetHead", fp(OFF(SetHead, p0)), fp(OFF(SetHead, p1)), fp(OFF(SetHead, p2)), fp(OFF(SetHead, p3)),
             fp(OFF(SetHead, p4)), fp(OFF(SetHead, p5)));
      break;
    case __lc_id_SetHead3f: three("SetHeadOnly", param<V3f>(rec, OFF(SetHead3f, p0))); break;
    case __lc_id_RollToVert: l.name("RollToVert"); break;
    case __lc_id_RotateXYZ:
    case __lc_id_RotateHLU:
    case __lc_id_Rotate: {
      V3f a = param<V3f>(rec, OFF(RotateXYZ, p0));
      // lpfg turns Rotate into RotateXYZ.
      l.call(id == __lc_id_RotateHLU ? "RotateHLU" : "RotateXYZ", a.x, a.y, a.z, fp(OFF(RotateXYZ, p1)));
      break;
    }
    case __lc_id_Surface: {
      float s = fp(OFF(Surface, p1));
      l.call("Surface", ip(OFF(Surface, p0)), s, s, s);
      break;
    }
    case __lc_id_Surface3:
      l.call("Surface", ip(OFF(Surface3, p0)), fp(OFF(Surface3, p1)), fp(OFF(Surface3, p2)), fp(OFF(Surface3, p3)));
      break;
    case __lc_id_Mesh: {
      float s = fp(OFF(Mesh, p1));
      l.call("Mesh", ip(OFF(Mesh, p0)), s, s, s);
      break;
    }
    case __lc_id_Mesh3: l.call("Mesh", ip(OFF(Mesh3, p0)), fp(OFF(Mesh3, p1)), fp(OFF(Mesh3, p2)), fp(OFF(Mesh3, p3))); break;
    case __lc_id_BSurface: {
      float s = fp(OFF(BSurface, p1));
      l.call("BSurface", ip(OFF(BSurface, p0)), s, s, s);
      break;
    }
    case __lc_id_DBSurfaceS: l.name("DBSurfaceS(surface)"); break;
    case __lc_id_DBSurfaceM: l.name("DBSurfaceM(surface)"); break;
    case __lc_id_SetElasticity: l.call("SetElasticity", ip(OFF(SetElasticity, p0)), fp(OFF(SetElasticity, p1))); break;
    case __lc_id_IncElasticity: l.call("IncElasticity", ip(OFF(IncElasticity, p0))); break;
    case __lc_id_DecElasticity: l.call("DecElasticity", ip(OFF(DecElasticity, p0))); break;
    case __lc_id_Elasticity: l.call("Elasticity", fp(OFF(Elasticity, p0))); break;
    case __lc_id_SetTropismDirection3f: {
      V3f v = param<V3f>(rec, OFF(SetTropismDirection3f, p0));
      char b[128];
      std::snprintf(b, sizeof b, "STropismDirection(%f,%f,%f)", v.x, v.y, v.z);
      out += b;
      break;
    }
    case __lc_id_CurrentContour: l.call("CurrentContour", ip(OFF(CurrentContour, p0))); break;
    case __lc_id_BlendedContour:
      l.call("BlendContours", ip(OFF(BlendedContour, p0)), ip(OFF(BlendedContour, p1)), fp(OFF(BlendedContour, p2)));
      break;
    case __lc_id_ScaleContour: l.call("ScaleContour", fp(OFF(ScaleContour, p0)), fp(OFF(ScaleContour, p1))); break;
    case __lc_id_ContourSides: l.call("ContourSides", ip(OFF(ContourSides, p0))); break;
    case __lc_id_ContourNormal: {
      V3f v = param<V3f>(rec, OFF(ContourNormal, p0));
      char b[128];
      std::snprintf(b, sizeof b, "ContourNormal(%f,%f,%f)", v.x, v.y, v.z);
      out += b;
      break;
    }
    case __lc_id_CurrentTexture: l.call("CurrentTexture", ip(OFF(CurrentTexture, p0))); break;
    case __lc_id_TextureVCoeff: l.call("TextureVCoeff", fp(OFF(TextureVCoeff, p0))); break;
    case __lc_id_StartGC: l.name("StartGC"); break;
    case __lc_id_PointGC: l.name("PointGC"); break;
    case __lc_id_EndGC: l.name("EndGC"); break;
    case __lc_id_SP: l.name("StartPolygon"); break;
    case __lc_id_EP: l.name("EndPolygon"); break;
    case __lc_id_PP: l.name("PolygonPoint"); break;
    case __lc_id_Rhombus: l.call("Rhombus", fp(OFF(Rhombus, p0)), fp(OFF(Rhombus, p1))); break;
    case __lc_id_Triangle: l.call("Triangle", fp(OFF(Triangle, p0)), fp(OFF(Triangle, p1))); break;
    case __lc_id_Orient: l.name("Orient"); break;
    case __lc_id_DSurface: l.name("DSurface(surface, true)"); break;
    case __lc_id_InitSurface: l.call("InitSurface", ip(OFF(InitSurface, p0))); break;
    case __lc_id_SurfacePoint:  // sic: lpfg's spelling
      l.call("SurfcePoint", ip(OFF(SurfacePoint, p0)), ip(OFF(SurfacePoint, p1)), ip(OFF(SurfacePoint, p2)));
      break;
    case __lc_id_DrawSurface:
      l.call("DrawSurface", ip(OFF(DrawSurface, p0))), l.end(), l.name("DSurface(surface, false)");
      break;
    case __lc_id_SetUPrecision: l.call("SetUPrecision", ip(OFF(SetUPrecision, p0))); break;
    case __lc_id_SetVPrecision: l.call("SetVPrecision", ip(OFF(SetVPrecision, p0))); break;
    case __lc_id_Camera: l.name("Camera"); break;
    case __lc_id_Terrain: l.name("Terrain(camera)"); break;
    case __lc_id_E1: l.call("E1", fp(OFF(E1, p0))); break;
    case __lc_id_E2: l.call("E2", fp(OFF(E2, p0)), fp(OFF(E2, p1))); break;
    default: return;  // not a turtle command lpfg writes
  }
#undef OFF
  l.end();
}

}  // namespace lcjit::runtime
