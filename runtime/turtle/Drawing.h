// Everything a picture of a model needs besides its string: the view file, colours, contours,
// shapes and textures, as loaded from the vlab object's files (manual §1.1.2, §8.2).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "runtime/turtle/Shapes.h"
#include "runtime/Terrain.h"
#include "runtime/turtle/Turtle.h"
#include "runtime/files/Contours.h"
#include "runtime/files/Images.h"
#include "runtime/files/Palette.h"
#include "runtime/files/ViewFile.h"

namespace lcjit::runtime {

struct DrawingFiles {
  ViewSettings view;
  Palette palette;
  ContourStore contours;
  ShapeLibrary shapes;
  std::vector<Image> textures;
  std::vector<std::string> textureFiles;  // resolved paths, by texture id
  std::vector<std::string> shapeFiles;    // resolved paths of the surfaces and meshes read
  // The view file's `terrain:` (§10.3). Model functions change it, and it stays with the view
  // file: shared by copies that keep the view, replaced when the view file is read again.
  std::shared_ptr<Terrain> terrain;

  TurtleSetup turtleSetup() const {
    TurtleSetup s;
    s.view = &view;
    s.contours = &contours;
    s.shapes = &shapes;
    s.terrain = terrain.get();
    s.textures = &textures;
    if (!view.views.empty() && view.views[0].dir) s.viewDirection = view.views[0].dir->Normalized();
    return s;
  }
};

}  // namespace lcjit::runtime
