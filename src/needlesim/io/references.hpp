#pragma once
// The publications the docs and reports cite as "seed NNN", read from docs/references.md
// (compiled into the binary), so a report lists the full citation of every seed it names.
#include <map>
#include <set>
#include <string>
#include <string_view>

namespace needlesim::io {

// seed number ("003") -> the citation as plain text (markdown emphasis dropped, links as "text (url)").
const std::map<std::string, std::string>& seedCitations();

// The seed numbers `text` cites ("seed 003", "seeds 002").
std::set<std::string> citedSeeds(std::string_view text);

}  // namespace needlesim::io
