// Runs a fuzz target's inputs without libFuzzer, so that any build (the GCC release build, the
// sanitizer build) replays the committed regressions and seeds as a test. Each argument is an
// input file or a directory of them (replayed in name order); a path that does not exist is
// an error, so that a moved directory does not turn the test into a no-op.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

void replay(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  const std::vector<char> bytes{std::istreambuf_iterator<char>(in),
                                std::istreambuf_iterator<char>()};
  LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t count = 0;
  for (int k = 1; k < argc; ++k) {
    const fs::path arg(argv[k]);
    std::vector<fs::path> files;
    if (fs::is_directory(arg)) {
      for (const auto& e : fs::directory_iterator(arg))
        if (e.is_regular_file()) files.push_back(e.path());
      std::sort(files.begin(), files.end());
    } else if (fs::is_regular_file(arg)) {
      files.push_back(arg);
    } else {
      std::cerr << "replay: " << arg << " is neither a file nor a directory\n";
      return 2;
    }
    for (const auto& f : files) {
      std::cerr << "replay: " << f.string() << "\n";
      replay(f);
      ++count;
    }
  }
  std::cerr << "replay: " << count << " inputs, no failure\n";
  return 0;
}
