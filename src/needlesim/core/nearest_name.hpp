#pragma once
// "Did you mean ...?" for a misspelt name: the known name with the fewest
// single-character edits (insert, delete, replace, swap of neighbours).
#include <string>
#include <vector>

namespace needlesim {

// Edits between a and b, case-insensitive (optimal string alignment distance).
std::size_t editDistance(const std::string& a, const std::string& b);

// The known name closest to `word`, or "" when none is close enough to be a
// likely typo (at most one edit per three characters of the word, at least one).
std::string nearestName(const std::string& word, const std::vector<std::string>& known);

}  // namespace needlesim
