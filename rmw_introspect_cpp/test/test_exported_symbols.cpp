// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The library exports exactly the rmw_* functions listed in exported_symbols.txt (what
// rmw_fastrtps_cpp exports) plus the two rcutils clocks of the virtual clock and the four
// interposed sleeps of the C library, and nothing else of librmw's or librcutils' own
// (rmw_validate_*, rcutils_get_zero_initialized_*, ...).

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <set>
#include <string>

namespace
{
std::set<std::string> read_list(const std::string & path)
{
  std::set<std::string> out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      continue;
    }
    out.insert(line);
  }
  return out;
}

std::set<std::string> exported_symbols(const std::string & library)
{
  std::set<std::string> out;
  const std::string command = "nm -D --defined-only '" + library + "'";
  FILE * pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) {
    return out;
  }
  char line[1024];
  while (fgets(line, sizeof(line), pipe) != nullptr) {
    // "<address> <type> <name>"
    std::string s(line);
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) {
      s.pop_back();
    }
    const size_t last = s.rfind(' ');
    if (last != std::string::npos) {
      out.insert(s.substr(last + 1));
    }
  }
  pclose(pipe);
  return out;
}
}  // namespace

TEST(ExportedSymbols, exactly_the_rmw_api)
{
  const auto expected = read_list(std::string(RMWI_TEST_DATA_DIR) + "/exported_symbols.txt");
  // 95 rmw_* + rcutils_steady_time_now, rcutils_system_time_now + the four sleeps
  ASSERT_EQ(101u, expected.size());
  const std::set<std::string> sleeps = {"clock_nanosleep", "nanosleep", "usleep", "sleep"};
  const auto exported = exported_symbols(RMWI_LIBRARY_FILE);
  ASSERT_FALSE(exported.empty()) << "nm found no symbols in " << RMWI_LIBRARY_FILE;
  std::set<std::string> rmw_exported;
  for (const auto & name : exported) {
    if (name.rfind("rmw_", 0) == 0 || name.rfind("rcutils_", 0) == 0 || sleeps.count(name) > 0) {
      rmw_exported.insert(name);
    }
    EXPECT_NE(0u, name.rfind("rmw_validate_", 0)) << "must not define " << name;
  }
  for (const auto & name : expected) {
    EXPECT_EQ(1u, rmw_exported.count(name)) << "missing export " << name;
  }
  for (const auto & name : rmw_exported) {
    EXPECT_EQ(1u, expected.count(name)) << "unexpected export " << name;
  }
  // Nothing else of note: no C++ symbols (mangled names) leak out.
  for (const auto & name : exported) {
    EXPECT_NE(0u, name.rfind("_Z", 0)) << "C++ symbol exported: " << name;
  }
}
