#pragma once
// The examples check their own physics: each check prints "ok" or "FAIL",
// and finish() turns the count into the program's exit status (so the
// tests that run the examples fail when the physics does).
#include <iostream>
#include <string>

namespace example {

inline int& failures() {
  static int count = 0;
  return count;
}

inline void check(bool ok, const std::string& what) {
  std::cout << (ok ? "  ok   " : "  FAIL ") << what << "\n";
  if (!ok) ++failures();
}

/// Prints the verdict; the exit status for main().
inline int finish() {
  std::cout << (failures() == 0 ? "all checks passed\n" : "SOME CHECKS FAILED\n");
  return failures() == 0 ? 0 : 1;
}

}  // namespace example
