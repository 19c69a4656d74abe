// The main of a fuzz target built without libFuzzer (the Release tree, g++): each file named
// on the command line is read and given to LLVMFuzzerTestOneInput once, as libFuzzer does
// with file arguments. A seed that breaks a target's invariants then fails the Release
// ctest (fuzz_seeds.TARGET) within seconds, before the sanitizer tree is built; the fuzzing
// itself stays in the ASan tree (fuzz.TARGET).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SEED_FILE...\n", argv[0]);
    return 2;
  }
  for (int i = 1; i < argc; ++i) {
    std::ifstream in(argv[i], std::ios::binary);
    if (!in) {
      std::fprintf(stderr, "%s: cannot read %s\n", argv[0], argv[i]);
      return 2;
    }
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::fprintf(stderr, "seed %s (%zu bytes)\n", argv[i], bytes.size());
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  }
  std::fprintf(stderr, "%d seeds: every one kept the target's invariants\n", argc - 1);
  return 0;
}
