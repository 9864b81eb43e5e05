// Symmetry lists (Symmetry.h). Each group is written as the sequence of AGG operations that makes
// its transforms (translate to the centre, rotate, flip or reflect, translate back and along the
// glide), in Context Free 3.4's order and with its constants, so that the copies it draws are
// placed exactly as cfdg places them.
#include "runtime/cfdg/Symmetry.h"

#include <agg_trans_affine.h>

#include <cmath>

namespace lcjit::runtime::cfdg {
namespace {

// The symmetry flags' values (CF::Cyclic …), as Context Free numbers them.
enum Group : int {
  Cyclic = 31 << 15, Dihedral = 1 << 15, P11g = 2 << 15, P11m = 3 << 15, P1m1 = 4 << 15, P2 = 30 << 15,
  P2mg = 6 << 15, P2mm = 7 << 15, Pm = 8 << 15, Pg = 9 << 15, Cm = 10 << 15, Pmm = 11 << 15, Pmg = 12 << 15,
  Pgg = 13 << 15, Cmm = 14 << 15, P4 = 15 << 15, P4m = 16 << 15, P4g = 17 << 15, P3 = 18 << 15,
  P3m1 = 19 << 15, P31m = 20 << 15, P6 = 21 << 15, P6m = 22 << 15
};

using T = agg::trans_affine;

T translated(double x, double y) { return agg::trans_affine_translation(x, y); }

class Builder {
 public:
  Builder(bool tiled, const Affine& tile)
      : tiled_(tiled), tile_(tile.sx, tile.shy, tile.shx, tile.sy, tile.tx, tile.ty) {
    const T& t = tile_;
    frieze_ = (t.sx != 0.0 || t.sy != 0.0) && t.sx * t.sy == 0.0;
    rhombic_ = tiled && ((std::fabs(t.shy) <= 0.0000001 && std::fabs(t.shx / t.sx - 0.5) < 0.0000001) ||
                         (std::fabs(t.shx) <= 0.0000001 && std::fabs(t.shy / t.sy - 0.5) < 0.0000001));
    rectangular_ = tiled && t.shx == 0.0 && t.shy == 0.0;
    square_ = rectangular_ && t.sx == t.sy;
    size45_ = t.sx;
    if (rhombic_) {
      // The lattice's two sides: equal (hexagonal), or one √2 times the other (a square turned 45°).
      double x1 = 1.0, y1 = 0.0, x2 = 0.0, y2 = 1.0;
      t.transform(&x1, &y1);
      t.transform(&x2, &y2);
      const double side10 = std::sqrt(x1 * x1 + y1 * y1), side01 = std::sqrt(x2 * x2 + y2 * y2);
      hexagonal_ = std::fabs(side10 / side01 - 1.0) < 0.0000001;
      square45_ = std::fabs(side01 / side10 - M_SQRT2) < 0.0000001 || std::fabs(side10 / side01 - M_SQRT2) < 0.0000001;
      size45_ = std::fmin(side01, side10);
    }
  }

  void add(const T& t) {
    for (const T& o : ops_)
      if (o == t) return;
    ops_.push_back(t);
  }

  void item(const __cf_SymmetryItem& it) {
    switch (it.kind) {
      case __cf_SymmetryFlag:
        if (collecting_) group();
        at_ = it.at ? it.at : "";
        collecting_ = true;
        spec_.assign(it.values, it.values + it.count);
        return;
      case __cf_SymmetryNumbers:
        if (!collecting_) throw SettingError{it.at ? it.at : "", "Symmetry flag expected here"};
        spec_.insert(spec_.end(), it.values, it.values + it.count);
        return;
      default:
        if (collecting_) group();
        collecting_ = false;
        add(T(it.values[0], it.values[1], it.values[2], it.values[3], it.values[4], it.values[5]));
        return;
    }
  }

  std::vector<Affine> finish() {
    if (collecting_) group();
    std::vector<Affine> out;
    for (const T& t : ops_) out.push_back({t.sx, t.shy, t.shx, t.sy, t.tx, t.ty});
    return out;
  }

 private:
  bool tiled_;
  T tile_;
  bool frieze_ = false, rhombic_ = false, rectangular_ = false, square_ = false, hexagonal_ = false, square45_ = false;
  double size45_ = 0;
  std::vector<T> ops_;
  std::vector<double> spec_;  // the flag, then its numbers
  std::string at_;
  bool collecting_ = false;

  [[noreturn]] void error(const std::string& message) const { throw SettingError{at_, message}; }

  // Rotations by multiples of 360°/order about (x, y), each followed by its reflection across the
  // line through (x, y) at `angle` (radians) when `mirrored`.
  void rotations(double order, double x, double y, bool mirrored, double angle) {
    if (order < 1.0) error("Rotational symmetry order must be one or larger");
    T toCentre;
    toCentre.translate(-x, -y);
    const agg::trans_affine_reflection mirror(angle);
    const int count = static_cast<int>(order);
    const double step = 2.0 * M_PI / order;
    for (int i = 0; i < count; ++i) {
      T turned(toCentre);
      if (i) turned.rotate(i * step);
      T reflected(turned);
      reflected *= mirror;
      turned.translate(x, y);
      reflected.translate(x, y);
      add(turned);
      if (mirrored) add(reflected);
    }
  }

  // An optional centre (or glide axis crossing): none, or two numbers after the flag.
  void centre(double& x, double& y, const char* message) {
    x = y = 0.0;
    if (spec_.size() == 3) x = spec_[1], y = spec_[2];
    else if (spec_.size() != 1) error(message);
  }
  // The axis number and its optional position, for pm, pg and cm.
  int axisAndOffset(double& offset, const char* message) {
    offset = 0.0;
    if (spec_.size() == 3) offset = spec_[2];
    else if (spec_.size() != 2) error(message);
    return static_cast<int>(spec_[1]);
  }
  // Of the two candidate centres a ± d, the one nearer 0.
  static double nearer(double a, double d) { return std::fabs(a + d) < std::fabs(a - d) ? a + d : a - d; }

  void group() {
    const int flag = static_cast<int>(spec_[0]);
    const T& tile = tile_;
    const size_t n = spec_.size();
    static const agg::trans_affine_reflection ref45(M_PI_4), ref135(-M_PI_4);
    const double r2 = M_SQRT1_2;
    if (flag >= P11g && flag <= P2mm && !frieze_) error("Frieze symmetry only works in frieze designs");
    if (flag >= Pm && flag <= P6m && !tiled_) error("Wallpaper symmetry only works in tiled designs");
    if (flag == P2 && !frieze_ && !tiled_) error("p2 symmetry only works in frieze or tiled designs");
    switch (flag) {
      case Cyclic: {
        if (n != 2 && n != 4) error("Cyclic symmetry requires an order argument and an optional center of rotation");
        rotations(spec_[1], n == 4 ? spec_[2] : 0.0, n == 4 ? spec_[3] : 0.0, false, 0.0);
        break;
      }
      case Dihedral: {
        // order [, mirror angle in degrees] [, centre x, y]
        double angle = 0.0, x = 0.0, y = 0.0;
        if (n == 3 || n == 5) angle = spec_[2] * M_PI / 180.0;
        if (n == 5) x = spec_[3], y = spec_[4];
        if (n == 4) x = spec_[2], y = spec_[3];
        if (n < 2 || n > 5)
          error("Dihedral symmetry requires an order argument, an optional mirror angle, and an optional center of rotation");
        rotations(spec_[1], x, y, true, angle);
        break;
      }
      case P11g:
      case P11m:
      case P1m1: {
        // A glide or a mirror along the frieze (p11g, p11m: the axis is across the frieze's
        // direction of repetition, at the given distance), or a mirror across it (p1m1).
        double mx = 0.0, my = 0.0;
        const bool along = tile.sx != 0.0;
        if (n == 2) (along == (flag != P1m1) ? my : mx) = spec_[1];
        else if (n > 2)
          error(flag == P11g ? "p11g symmetry takes no arguments or an optional glide axis position argument"
                : flag == P11m ? "p11m symmetry takes no arguments or an optional mirror axis position argument"
                               : "p1m1 symmetry takes no arguments or an optional mirror axis position argument");
        add(T());
        T t;
        t.translate(-mx, -my);
        if (along == (flag != P1m1)) t.flip_y();
        else t.flip_x();
        if (flag == P11g) t.translate(tile.sx * 0.5 + mx, tile.sy * 0.5 + my);
        else t.translate(mx, my);
        add(t);
        break;
      }
      case P2: {
        double x, y;
        centre(x, y, "p2 symmetry takes no arguments or a center of rotation");
        rotations(2.0, x, y, false, 0.0);
        break;
      }
      case P2mg: {
        double x, y;
        centre(x, y, "p2mg symmetry takes no arguments or a center of rotation");
        T glideX = translated(-x, -y), half = translated(-x, -y), glideY = translated(-x, -y);
        glideX.flip_x();
        half.flip_x();
        half.flip_y();
        glideY.flip_y();
        glideX.translate(tile.sx * 0.5 + x, tile.sy * 0.5 + y);
        half.translate(x, y);
        glideY.translate(tile.sx * 0.5 + x, tile.sy * 0.5 + y);
        add(T());
        add(glideX);
        add(half);
        add(glideY);
        break;
      }
      case P2mm: {
        double x, y;
        centre(x, y, "p2mm symmetry takes no arguments or a center of relection");
        rotations(2.0, x, y, true, 0.0);
        break;
      }
      case Pm:
      case Pg:
      case Cm: {
        const char* name = flag == Pm ? "pm" : flag == Pg ? "pg" : "cm";
        const std::string g = name;
        if (flag == Cm ? (!rhombic_ && !square_) : (!rectangular_ && !square45_))
          error(g + (flag == Cm ? " symmetry requires diamond tiling" : " symmetry requires rectangular tiling"));
        double off;
        const int axis = axisAndOffset(off, (g + (flag == Pg ? " symmetry takes a glide axis argument and an optional axis position argument"
                                                             : " symmetry takes a mirror axis argument and an optional axis position argument")).c_str());
        add(T());
        // pm and pg tell the axes of a rectangle from those of a square turned 45°; cm those of a
        // rhombus from those of a square.
        const bool plain = flag == Cm ? rhombic_ : rectangular_;
        const bool turned = flag == Cm ? square_ : square45_;
        if (plain && (axis < 0 || axis > 1)) error(g + " symmetry mirror axis argument must be 0 or 1");
        else if (turned && (axis < 2 || axis > 3)) error(g + " symmetry mirror axis argument must be 2 or 3");
        T t;
        const bool glide = flag == Pg;
        switch (axis) {
          case 0:  // the x axis
            t.translate(0, -off);
            t.flip_y();
            t.translate(glide ? tile.sx * 0.5 : 0.0, off);
            break;
          case 1:  // the y axis
            t.translate(-off, 0);
            t.flip_x();
            t.translate(off, glide ? tile.sy * 0.5 : 0.0);
            break;
          case 2:  // the line x = y
            if (flag == Cm) t.translate(off * r2, -off * r2);
            else t.translate(-off * r2, off * r2);
            t *= ref45;
            if (glide) t.translate((off + size45_ * 0.5) * r2, (-off + size45_ * 0.5) * r2);
            else if (flag == Cm) t.translate(-off * r2, off * r2);
            else t.translate(off * r2, -off * r2);
            break;
          case 3:  // the line x = -y
            t.translate(-off * r2, -off * r2);
            t *= ref135;
            if (glide) t.translate((off - size45_ * 0.5) * r2, (off + size45_ * 0.5) * r2);
            else t.translate(off * r2, off * r2);
            break;
          default:
            error(g + (glide ? " symmetry glide axis argument must be 0, 1, 2, or 3"
                             : " symmetry mirror axis argument must be 0, 1, 2, or 3"));
        }
        add(t);
        break;
      }
      case Pmm: {
        if (!rectangular_ && !square45_) error("pmm symmetry requires rectangular tiling");
        double x, y;
        centre(x, y, "pmm symmetry takes no arguments or a center of reflection");
        rotations(2.0, x, y, true, square45_ ? M_PI_4 : 0.0);
        break;
      }
      case Pmg: {
        if (!rectangular_ && !square45_) error("pmg symmetry requires rectangular tiling");
        double x = 0.0, y = 0.0;
        if (n == 4) x = spec_[2], y = spec_[3];
        else if (n != 2) error("pmg symmetry takes a mirror axis argument and an optional center of reflection");
        const int axis = static_cast<int>(spec_[1]);
        if (rectangular_ && (axis < 0 || axis > 1)) error("pmg symmetry mirror axis argument must be 0 or 1");
        else if (square45_ && (axis < 2 || axis > 3)) error("pmg symmetry mirror axis argument must be 2 or 3");
        T mirror, glide;
        switch (axis) {
          case 0:
            rotations(2.0, x, nearer(y, 0.25 * tile.sy), false, 0.0);
            mirror.translate(-x, 0.0);
            mirror.flip_x();
            mirror.translate(x, 0.5 * tile.sy);
            glide.translate(0.0, -y);
            glide.flip_y();
            glide.translate(0.0, y);
            break;
          case 1:
            rotations(2.0, nearer(x, 0.25 * tile.sx), y, false, 0.0);
            mirror.translate(-x, 0.0);
            mirror.flip_x();
            mirror.translate(x, 0.0);
            glide.translate(0.0, -y);
            glide.flip_y();
            glide.translate(0.5 * tile.sx, y);
            break;
          case 2:
          case 3: {
            // The rotation centre: of two points a quarter diagonal from (x, y), the one nearer the origin.
            const double d = 0.25 * r2 * size45_;
            double cx = axis == 2 ? x - d : x + d, cy = y + d;
            const double cx2 = axis == 2 ? x + d : x - d, cy2 = y - d;
            if (cx2 * cx2 + cy2 * cy2 < cx * cx + cy * cy) cx = cx2, cy = cy2;
            rotations(2.0, cx, cy, false, 0.0);
            mirror.translate(-x, -y);
            mirror *= axis == 2 ? ref45 : ref135;
            mirror.translate(x, y);
            glide.translate(-x, -y);
            glide *= axis == 2 ? ref135 : ref45;
            if (axis == 2) glide.translate(x - size45_ * r2 * 0.5, y + size45_ * r2 * 0.5);
            else glide.translate(x + size45_ * r2 * 0.5, y + size45_ * r2 * 0.5);
            break;
          }
          default: error("pmg symmetry mirror axis argument must be 0, 1, 2, or 3");
        }
        add(mirror);
        add(glide);
        break;
      }
      case Pgg: {
        if (!rectangular_ && !square45_) error("pgg symmetry requires rectangular tiling");
        double x, y;
        centre(x, y, "pgg symmetry takes no arguments or a center of glide axis intersection");
        T first, second;
        if (square45_) {
          // The rotation centre: of the four points a quarter diagonal from (x, y) along the axes,
          // the first nearest the origin.
          double cx = x + 0.25 * M_SQRT2 * size45_, cy = y;
          const double others[3][2] = {{x - 0.25 * M_SQRT2 * size45_, y},
                                       {x, y + 0.25 * M_SQRT2 * size45_},
                                       {x, y - 0.25 * M_SQRT2 * size45_}};
          for (const auto& o : others)
            if (o[0] * o[0] + o[1] * o[1] < cx * cx + cy * cy) cx = o[0], cy = o[1];
          rotations(2.0, cx, cy, false, 0.0);
          first.translate(-x, -y);
          first *= ref45;
          first.translate(x + size45_ * r2 * 0.5, y + size45_ * r2 * 0.5);
          second.translate(-x, -y);
          second *= ref135;
          second.translate(x - size45_ * r2 * 0.5, y + size45_ * r2 * 0.5);
        } else {
          rotations(2.0, nearer(x, 0.25 * tile.sx), nearer(y, 0.25 * tile.sy), false, 0.0);
          first.translate(-x, 0.0);
          first.flip_x();
          first.translate(x, 0.5 * tile.sy);
          second.translate(0.0, -y);
          second.flip_y();
          second.translate(0.5 * tile.sx, y);
        }
        add(first);
        add(second);
        break;
      }
      case Cmm: {
        if (!rhombic_ && !square_) error("cmm symmetry requires diamond tiling");
        double x, y;
        centre(x, y, "cmm symmetry takes no arguments or a center of reflection");
        rotations(2.0, x, y, true, square45_ ? M_PI_4 : 0.0);
        break;
      }
      case P4:
      case P4m: {
        if (!square_ && !square45_) error("p4 & p4m symmetry requires square tiling");
        double x, y;
        centre(x, y, "p4 & p4m symmetry takes no arguments or a center of rotation");
        rotations(4.0, x, y, flag == P4m, square_ ? M_PI_4 : 0.0);
        break;
      }
      case P4g: {
        if (!square_ && !square45_) error("p4g symmetry requires square tiling");
        double x, y;
        centre(x, y, "p4g symmetry takes no arguments or a center of rotation");
        T toCentre;
        toCentre.translate(-x, -y);
        T glide(toCentre);
        if (square45_) {
          glide.translate(-size45_ * 0.25 * r2, -size45_ * 0.25 * r2);
          glide *= ref135;
          glide.translate(-size45_ * 0.25 * r2, size45_ * 0.75 * r2);
        } else {
          glide.translate(tile.sx * 0.25, 0.0);
          glide.flip_x();
          glide.translate(-tile.sx * 0.25, tile.sy * 0.5);
        }
        for (int i = 0; i < 4; ++i) {
          T turned(toCentre), glided(glide);
          if (i) {
            turned.rotate(i * M_PI_2);
            glided.rotate(i * M_PI_2);
          }
          turned.translate(x, y);
          glided.translate(x, y);
          add(turned);
          add(glided);
        }
        break;
      }
      case P3: {
        if (!hexagonal_) error("p3 symmetry requires hexagonal tiling");
        double x, y;
        centre(x, y, "p3 symmetry takes no arguments or a center of rotation");
        rotations(3.0, x, y, false, 0.0);
        break;
      }
      case P3m1:
      case P31m: {
        if (!hexagonal_) error("p3m1 & p31m symmetry requires hexagonal tiling");
        double x, y;
        centre(x, y, "p3m1 & p31m symmetry takes no arguments or a center of rotation");
        // The mirrors at 30° or 60°, by the lattice's slant and the group.
        const bool deg30 = (std::fabs(tile.shx) <= 0.000001) != (flag == P3m1);
        rotations(3.0, x, y, true, M_PI / (deg30 ? 6.0 : 3.0));
        break;
      }
      case P6:
      case P6m: {
        if (!hexagonal_) error("p6 & p6m symmetry requires hexagonal tiling");
        double x, y;
        centre(x, y, "p6 & p6m symmetry takes no arguments or a center of rotation");
        rotations(6.0, x, y, flag == P6m, 0.0);
        break;
      }
      default: error("Unknown symmetry type");
    }
    spec_.clear();
  }
};

}  // namespace

std::vector<Affine> symmetryTransforms(const __cf_SymmetryItem* items, int count, bool tiled, const Affine& tile) {
  Builder b(tiled, tile);
  for (int i = 0; i < count; ++i) b.item(items[i]);
  return b.finish();
}

}  // namespace lcjit::runtime::cfdg
