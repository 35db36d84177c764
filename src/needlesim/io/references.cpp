#include "needlesim/io/references.hpp"

#include <regex>
#include <sstream>

#include "needlesim/core/embedded.hpp"

namespace needlesim::io {

namespace {

// Markdown of a table cell as plain text: "*A*" -> "A", "[t](u)" -> "t (u)".
std::string plainText(std::string cell) {
  cell = std::regex_replace(cell, std::regex(R"(\[([^\]]*)\]\(([^)]*)\))"), "$1 ($2)");
  cell = std::regex_replace(cell, std::regex(R"(\*)"), "");
  const auto first = cell.find_first_not_of(' '), last = cell.find_last_not_of(' ');
  return first == std::string::npos ? std::string() : cell.substr(first, last - first + 1);
}

std::map<std::string, std::string> parseReferences(std::string_view markdown) {
  std::map<std::string, std::string> out;
  static const std::regex row(R"(^\| (\d{3}) \|([^|]*)\|)");
  std::istringstream in{std::string(markdown)};
  std::smatch m;
  for (std::string line; std::getline(in, line);)
    if (std::regex_search(line, m, row)) out[m[1].str()] = plainText(m[2].str());
  return out;
}

}  // namespace

const std::map<std::string, std::string>& seedCitations() {
  static const std::map<std::string, std::string> citations = parseReferences(embedded::kReferences);
  return citations;
}

std::set<std::string> citedSeeds(std::string_view text) {
  static const std::regex seed(R"(\bseeds? (\d{3})\b)");
  std::set<std::string> out;
  const std::string s(text);
  for (auto it = std::sregex_iterator(s.begin(), s.end(), seed); it != std::sregex_iterator(); ++it)
    out.insert((*it)[1].str());
  return out;
}

}  // namespace needlesim::io
