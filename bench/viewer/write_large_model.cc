// Writes the generated PR2-sized robot (large_model.h) into a folder, for measuring it by hand
// through the server, the viewer and its web page (docs/performance.md):
//   write_large_model DIR [ARMS LINKS_PER_ARM TRIANGLES]      (default 4 10 1000000)
#include <cstdio>
#include <cstdlib>

#include "bench/viewer/large_model.h"

int main(int argc, char** argv) {
  if (argc != 2 && argc != 5) {
    std::fprintf(stderr, "usage: write_large_model DIR [ARMS LINKS_PER_ARM TRIANGLES]\n");
    return 2;
  }
  const int arms = argc == 5 ? std::atoi(argv[2]) : 4;
  const int links_per_arm = argc == 5 ? std::atoi(argv[3]) : 10;
  const long long triangles = argc == 5 ? std::atoll(argv[4]) : 1'000'000;
  const auto model =
      mbstream::viewer::bench::WriteLargeModel(argv[1], arms, links_per_arm, triangles);
  std::printf("%s: %d links, %lld triangles\n", model.urdf.c_str(), model.links, model.triangles);
  return 0;
}
