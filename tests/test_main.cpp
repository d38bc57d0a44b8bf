// The main of every test binary: gtest's, run inside a temporary directory
// of the process's own. Tests write their scenes, meshes and images under
// std::filesystem::temp_directory_path() with fixed names; ctest runs several
// test processes at once (scripts/test.sh), so each process gets its own
// TMPDIR and two tests can never write the same file. The directory is
// removed at exit; CAUSTIX_KEEP_TEST_TMP=1 keeps it (its path is printed).

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);

  const char* base = std::getenv("TMPDIR");
  std::string pattern = std::string(base && *base ? base : "/tmp") + "/caustix_test_XXXXXX";
  const char* dir = ::mkdtemp(pattern.data());
  if (!dir) {
    std::perror(("test_main: mkdtemp " + pattern).c_str());
    return 1;
  }
  ::setenv("TMPDIR", dir, 1);

  const int rc = RUN_ALL_TESTS();

  const char* keep = std::getenv("CAUSTIX_KEEP_TEST_TMP");
  if (keep && std::string(keep) == "1") {
    std::printf("test_main: kept %s\n", dir);
  } else {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
  return rc;
}
