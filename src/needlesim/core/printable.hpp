#pragma once
// A user's text as it may appear in a message: at most `limit` characters,
// control and non-ASCII bytes written as \xNN, the full length named when cut.
#include <cstddef>
#include <string>

namespace needlesim {

std::string printableText(const std::string& s, std::size_t limit = 60);

}  // namespace needlesim
