#pragma once
/// @file Runs a shell command and returns what it printed, for the tests that ask tshark how
/// it decodes what the stack sent.

#include <array>
#include <cstdio>
#include <string>

namespace tb::its::test {

/// Standard output of `sh -c cmd`; empty when the command cannot be started.
inline std::string run_command(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr)
    return out;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0)
    out.append(buf.data(), n);
  pclose(p);
  return out;
}

}  // namespace tb::its::test
