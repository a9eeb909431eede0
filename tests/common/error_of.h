#pragma once
// The message of the exception a call throws, for tests that check an error's exact wording.

#include <exception>
#include <string>

namespace rome::test {

/// what() of the std::exception `f()` throws, or "(no error)" if it returns.
template <class F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const std::exception& e) { return e.what(); }
  return "(no error)";
}

}  // namespace rome::test
