// tinygltf's implementation, compiled here as its Debian README describes (instead of linking
// libtinygltf.so): the program then loads no shared library for it (docs/performance.md).
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
