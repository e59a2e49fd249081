// The message of the error that `action` throws, checked to be one line; the
// test fails if nothing is thrown. A template on the error type because
// headers come before module imports (TOOLCHAIN.md pitfall 2).
#pragma once
#include <doctest/doctest.h>
#include <string>

template <class Error, class Action>
std::string one_line_error(Action&& action, const std::string& context) {
  try {
    action();
  } catch (const Error& e) {
    const std::string what = e.what();
    CHECK_MESSAGE(what.find('\n') == std::string::npos, what);
    return what;
  }
  FAIL("expected an error for " << context);
  return {};
}
