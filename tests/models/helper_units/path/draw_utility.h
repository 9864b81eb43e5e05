// Found through CPLUS_INCLUDE_PATH; L+C in a header, as research models keep it.
#pragma once
inline void mark(float x) { nproduce Sphere(x); }
