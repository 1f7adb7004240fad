// Runs the `epi` program as a user would and captures what it prints, for the CLI tests.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

namespace {

struct EpiRun {
  int exit_code = -1;  // valid when signal == 0
  int signal = 0;      // the signal that killed epi, if one did
  std::string out;     // stdout and stderr together
};

EpiRun run_epi(const std::string& args) {
  const std::string command = std::string(EPI_BINARY_DIR) + "/bin/epi " + args + " 2>&1";
  EpiRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  if (WIFEXITED(status)) {
    run.exit_code = WEXITSTATUS(status);
    // The shell reports a child killed by signal s as exit code 128 + s.
    if (run.exit_code > 128 && run.exit_code < 128 + 64) run.signal = run.exit_code - 128, run.exit_code = -1;
  } else if (WIFSIGNALED(status)) {
    run.signal = WTERMSIG(status);
  }
  return run;
}

// A crash is never an expected failure: it is reported as such, whatever code was expected.
#define EXPECT_EXIT_CODE(run, code)                                             \
  do {                                                                          \
    EXPECT_EQ((run).signal, 0) << "epi was killed by a signal\n" << (run).out;  \
    EXPECT_EQ((run).exit_code, (code)) << (run).out;                            \
  } while (0)
#define ASSERT_EXIT_CODE(run, code)                                             \
  do {                                                                          \
    ASSERT_EQ((run).signal, 0) << "epi was killed by a signal\n" << (run).out;  \
    ASSERT_EQ((run).exit_code, (code)) << (run).out;                            \
  } while (0)

constexpr int kUsage = 2;  // the command line does not parse
constexpr int kFailed = 1;

}  // namespace
