// Plain C++ included before lpfgall.h: lpfg's translator starts at lpfgall.h, so a type named
// like a predefined module is no predecessor here.
struct Camera {
  float zoom;
};
Camera defaultCamera();
inline Camera defaultCamera() { return Camera{1}; }
