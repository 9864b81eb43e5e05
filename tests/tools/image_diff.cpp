// image_diff REFERENCE.png ACTUAL.png [--threshold T] [--max-fraction F]
// Compares two pictures pixel by pixel: a pixel differs when any channel differs by more than T
// (default 40 of 255, which absorbs rasteriser rounding between machines); the pictures match
// when at most F (default 0.001) of the pixels differ, plus 16 pixels of slack. A changed colour,
// a module that stops drawing or a shifted frame moves far more pixels than that.
// Exit status: 0 match, 1 differ, 2 usage or unreadable file. Writes ACTUAL.diff.png on failure.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: image_diff REFERENCE ACTUAL [--threshold T] [--max-fraction F]\n");
    return 2;
  }
  int threshold = 40;
  double maxFraction = 0.001;
  for (int i = 3; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--threshold")) threshold = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--max-fraction")) maxFraction = std::atof(argv[i + 1]);
  }
  int w1, h1, c1, w2, h2, c2;
  unsigned char* a = stbi_load(argv[1], &w1, &h1, &c1, 3);
  unsigned char* b = stbi_load(argv[2], &w2, &h2, &c2, 3);
  if (!a || !b) {
    std::fprintf(stderr, "image_diff: cannot read %s\n", !a ? argv[1] : argv[2]);
    return 2;
  }
  if (w1 != w2 || h1 != h2) {
    std::fprintf(stderr, "image_diff: sizes differ: %dx%d vs %dx%d\n", w1, h1, w2, h2);
    return 1;
  }
  size_t n = (size_t)w1 * h1, bad = 0;
  std::vector<unsigned char> diff(n * 3, 0);
  for (size_t i = 0; i < n; ++i) {
    int d = 0;
    for (int c = 0; c < 3; ++c) d = std::max(d, std::abs((int)a[i * 3 + c] - (int)b[i * 3 + c]));
    if (d > threshold) {
      ++bad;
      diff[i * 3] = 255;
    } else {
      diff[i * 3 + 1] = diff[i * 3 + 2] = (unsigned char)(a[i * 3] / 4);
    }
  }
  size_t allowed = (size_t)(maxFraction * (double)n) + 16;
  std::printf("image_diff: %zu of %zu pixels differ (allowed %zu)\n", bad, n, allowed);
  if (bad > allowed) {
    std::string out = std::string(argv[2]) + ".diff.png";
    stbi_write_png(out.c_str(), w1, h1, 3, diff.data(), w1 * 3);
    std::printf("image_diff: differences in red: %s\n", out.c_str());
    return 1;
  }
  return 0;
}
