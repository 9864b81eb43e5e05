// image_diff REFERENCE.png ACTUAL.png [--threshold T] [--max-fraction F]
// image_diff REFERENCE.png ACTUAL.png --exact
// Compares two pictures pixel by pixel: a pixel differs when any channel differs by more than T
// (default 40 of 255, which absorbs rasteriser rounding between machines); the pictures match
// when at most F (default 0.001) of the pixels differ, plus 16 pixels of slack. A changed colour,
// a module that stops drawing or a shifted frame moves far more pixels than that.
// --exact: the same size, the same channels (grey, grey+alpha, RGB, RGBA), the same bit depth
// and every sample equal: for pictures that must be another program's to the bit (a Context Free
// design's against cfdg's).
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

static int exactly(const char* reference, const char* actual) {
  int w1, h1, c1, w2, h2, c2;
  bool deep1 = stbi_is_16_bit(reference), deep2 = stbi_is_16_bit(actual);
  void* a = deep1 ? (void*)stbi_load_16(reference, &w1, &h1, &c1, 0) : (void*)stbi_load(reference, &w1, &h1, &c1, 0);
  void* b = deep2 ? (void*)stbi_load_16(actual, &w2, &h2, &c2, 0) : (void*)stbi_load(actual, &w2, &h2, &c2, 0);
  if (!a || !b) {
    std::fprintf(stderr, "image_diff: cannot read %s\n", !a ? reference : actual);
    return 2;
  }
  if (w1 != w2 || h1 != h2 || c1 != c2 || deep1 != deep2) {
    std::printf("image_diff: %dx%d, %d channels of %d bits; the reference %dx%d, %d channels of %d bits\n", w2, h2, c2,
                deep2 ? 16 : 8, w1, h1, c1, deep1 ? 16 : 8);
    return 1;
  }
  size_t samples = (size_t)w1 * h1 * c1, bad = 0;
  for (size_t i = 0; i < samples; ++i)
    bad += deep1 ? ((unsigned short*)a)[i] != ((unsigned short*)b)[i] : ((unsigned char*)a)[i] != ((unsigned char*)b)[i];
  std::printf("image_diff: %zu of %zu samples differ\n", bad, samples);
  return bad ? 1 : 0;
}

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: image_diff REFERENCE ACTUAL [--threshold T] [--max-fraction F]\n");
    return 2;
  }
  if (argc == 4 && !std::strcmp(argv[3], "--exact")) return exactly(argv[1], argv[2]);
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
