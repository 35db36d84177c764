// How InputError messages show user text: control and non-UTF-8 bytes escaped, long values cut.
#include <gtest/gtest.h>

#include <string>

#include "needlesim/core/error.hpp"

using namespace needlesim;

TEST(ErrorMessages, PrintableEscapesControlsAndKeepsUtf8) {
  EXPECT_EQ(printable("caf\xC3\xA9 5 \xC2\xB5m"), "caf\xC3\xA9 5 \xC2\xB5m");
  EXPECT_EQ(printable("a\x1b[2Jb\x07\n"), "a\\x1b[2Jb\\x07\\n");
  EXPECT_EQ(printable("caf\xE9"), "caf\\xe9");
  EXPECT_EQ(printable("\xC2\x9B" "31m"), "\\xc2\\x9b31m");  // the one-byte CSI of C1
  EXPECT_EQ(printable(std::string(100, 'y')), std::string(60, 'y') + "... (100 bytes)");
  EXPECT_EQ(utf8ErrorOffset("ok \xE2\x82\xAC"), std::string_view::npos);
  EXPECT_EQ(utf8ErrorOffset("ab\xED\xA0\x80"), 2u);  // a surrogate
  EXPECT_EQ(utf8ErrorOffset("ab\xC0\xAF"), 2u);      // an overlong '/'
}

TEST(ErrorMessages, InputErrorEscapesAndCutsEveryPart) {
  const InputError e(SourceLocation{"f\x1b.yaml", 3, 4}, "k\x07", std::string(500, 'v') + "\x1b", "is bad\r", "ok\n");
  const std::string msg = e.what();
  EXPECT_EQ(msg, "f\\x1b.yaml:3:4: k\\x07: is bad\\r (got '" + std::string(60, 'v') + "... (501 bytes)'); allowed: ok\\n");
}
