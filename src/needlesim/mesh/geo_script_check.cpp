// The lexical check of Gmsh scripts (geo_script_check.hpp). The refused words follow Gmsh's
// parser (Parser/Gmsh.l and Gmsh.y, Gmsh 4.8 to 4.13): the commands that act outside the model.
#include "needlesim/mesh/geo_script_check.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "needlesim/core/error.hpp"

namespace needlesim::mesh {

namespace fs = std::filesystem;

namespace {

constexpr const char* kAllowed =
    "a script that only builds geometry, sets options and meshes: no SystemCall, Save, Print, Printf to a file, "
    "Exit, Abort, ...; Include and Merge only of a \"quoted\" file in the script's folder (docs/scenario-format.md, "
    "\"What a .geo may contain\")";

// Commands refused wherever they appear, with what they would do.
const std::map<std::string, std::string>& refusedWords() {
  static const std::map<std::string, std::string> words = {
      {"SystemCall", "runs a program"},
      {"NonBlockingSystemCall", "runs a program"},
      {"System", "runs a program"},
      {"OnelabRun", "runs a program (a ONELAB client)"},
      {"OnelabAction", "steers a ONELAB client"},
      {"SendToServer", "sends data to a server"},
      {"Exit", "ends the program reading it"},
      {"Abort", "ends the program reading it"},
      {"Save", "writes a file"},
      {"Print", "writes a file"},
      {"CreateDir", "creates a folder"},
      {"DeleteFile", "deletes a file"},
      {"RenameFile", "renames a file"},
      {"Plugin", "runs a post-processing plugin (some write files)"},
      {"Sleep", "waits"},
      {"SetChanged", "is a graphical-interface command"},
      {"Draw", "is a graphical-interface command"},
      {"S2N", "turns text into a command or variable name, which cannot be checked"},
      {"StringToName", "turns text into a command or variable name, which cannot be checked"},
  };
  return words;
}

struct Token {
  enum Kind { Word, Text, Symbol } kind;
  std::string text;
  int line;
};

// Gmsh's lexer: // and /* */ comments, "..." and '...' strings (no escapes), words of letters,
// digits and _ (not starting with a digit), everything else one symbol (">>" one token).
std::vector<Token> tokens(const std::string& s) {
  std::vector<Token> out;
  int line = 1;
  std::size_t i = 0;
  auto advance = [&](std::size_t to) {
    line += static_cast<int>(std::count(s.begin() + static_cast<std::ptrdiff_t>(i), s.begin() + static_cast<std::ptrdiff_t>(std::min(to, s.size())), '\n'));
    i = std::min(to, s.size());
  };
  auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  while (i < s.size()) {
    const char c = s[i];
    if (s.compare(i, 2, "//") == 0) {
      advance(s.find('\n', i));
    } else if (s.compare(i, 2, "/*") == 0) {
      const auto end = s.find("*/", i + 2);
      advance(end == std::string::npos ? s.size() : end + 2);
    } else if (c == '"' || c == '\'') {
      const auto end = s.find(c, i + 1);
      const int at = line;
      const std::string text = s.substr(i + 1, (end == std::string::npos ? s.size() : end) - i - 1);
      advance(end == std::string::npos ? s.size() : end + 1);
      out.push_back({Token::Text, text, at});
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      std::size_t end = i;
      while (end < s.size() && word(s[end])) ++end;
      out.push_back({Token::Word, s.substr(i, end - i), line});
      i = end;
    } else if (std::isdigit(static_cast<unsigned char>(c))) {
      while (i < s.size() && (word(s[i]) || s[i] == '.')) ++i;  // a number (1e-3, 2.5)
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      advance(i + 1);
    } else {
      const bool twice = c == '>' && i + 1 < s.size() && s[i + 1] == '>';
      out.push_back({Token::Symbol, twice ? ">>" : std::string(1, c), line});
      i += twice ? 2 : 1;
    }
  }
  return out;
}

std::string lowerExtension(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

class ScriptCheck {
 public:
  explicit ScriptCheck(const fs::path& top) : folder_(fs::weakly_canonical(fs::absolute(top)).parent_path()) {}

  void check(const fs::path& script, int depth) {
    if (depth > 16) refuse(script, 0, "Include", "nests includes more than 16 deep", "");
    if (!seen_.insert(fs::weakly_canonical(script).string()).second) return;
    std::ifstream in(script, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    const auto t = tokens(text.str());
    for (std::size_t k = 0; k < t.size(); ++k) {
      if (t[k].kind != Token::Word) continue;
      const std::string& w = t[k].text;
      if (const auto refused = refusedWords().find(w); refused != refusedWords().end())
        refuse(script, t[k].line, w, refused->second, "");
      if (w == "Printf" || w == "Sprintf") checkPrintf(script, t, k);
      if (w == "Include" || w == "Merge" || w == "MergeWithBoundingBox") checkInclude(script, t, k, depth);
      if (w == "ShapeFromFile" || w == "ListFromFile") checkFileArgument(script, t, k);
    }
  }

 private:
  [[noreturn]] void refuse(const fs::path& script, int line, const std::string& command, const std::string& does,
                           const std::string& value) const {
    throw InputError(SourceLocation{script.string(), line, 0}, "tissue.geometry",
                     value.empty() ? command : command + " " + value,
                     fmt::format("this script command {}; reading a geometry never acts outside it", does), kAllowed);
  }

  // Printf(...) > "file" or >> "file" writes a file.
  void checkPrintf(const fs::path& script, const std::vector<Token>& t, std::size_t k) const {
    std::size_t j = k + 1;
    int depth = 0;
    for (; j < t.size(); ++j) {
      if (t[j].kind != Token::Symbol) continue;
      if (t[j].text == "(") ++depth;
      if (t[j].text == ")" && --depth == 0) break;
      if (t[j].text == ";") return;
    }
    if (j + 1 < t.size() && t[j + 1].kind == Token::Symbol && (t[j + 1].text == ">" || t[j + 1].text == ">>"))
      refuse(script, t[k].line, t[k].text + "(...) " + t[j + 1].text, "writes a file", "");
  }

  // The file a plain string literal names, relative to the script; refused unless it is in the
  // top script's folder.
  fs::path fileInFolder(const fs::path& script, const std::vector<Token>& t, std::size_t at, const std::string& command,
                        int line) const {
    if (at >= t.size() || t[at].kind != Token::Text)
      refuse(script, line, command, "reads a file named by an expression, which cannot be checked",
             "(not a \"quoted\" file name)");
    const fs::path named = t[at].text;
    const fs::path file = fs::weakly_canonical(named.is_absolute() ? named : script.parent_path() / named);
    const auto rel = file.lexically_relative(folder_);
    if (named.is_absolute() || rel.empty() || *rel.begin() == "..")
      refuse(script, line, command, fmt::format("reads {}, outside the script's folder {}", file.string(), folder_.string()),
             "\"" + printable(t[at].text) + "\"");
    if (lowerExtension(file) == ".gz")
      refuse(script, line, command, "reads a compressed file, which Gmsh uncompresses by running a program",
             "\"" + printable(t[at].text) + "\"");
    return file;
  }

  void checkInclude(const fs::path& script, const std::vector<Token>& t, std::size_t k, int depth) {
    const fs::path file = fileInFolder(script, t, k + 1, t[k].text, t[k].line);
    std::error_code ec;
    if (fs::is_regular_file(file, ec) && (t[k].text == "Include" || gmshReadsAsScript(file.string())))
      check(file, depth + 1);
  }

  // ShapeFromFile("x.brep"), ListFromFile["x.txt"]: a quoted file in the folder.
  void checkFileArgument(const fs::path& script, const std::vector<Token>& t, std::size_t k) const {
    const bool bracket = k + 1 < t.size() && t[k + 1].kind == Token::Symbol && (t[k + 1].text == "(" || t[k + 1].text == "[");
    fileInFolder(script, t, bracket ? k + 2 : t.size(), t[k].text, t[k].line);
  }

  fs::path folder_;
  std::set<std::string> seen_;
};

}  // namespace

bool gmshReadsAsScript(const std::string& path) {
  static const std::set<std::string> formats = {
      ".stl", ".brep", ".rle", ".brp", ".iges", ".igs", ".step", ".stp", ".sat", ".x_t", ".xmt_txt", ".x_b",
      ".xmt_bin", ".unv", ".vtk", ".wrl", ".vrml", ".iv", ".mesh", ".diff", ".med", ".mmed", ".rmed", ".bdf",
      ".nas", ".dat", ".p3d", ".pnm", ".pbm", ".pgm", ".ppm", ".bmp", ".jpg", ".jpeg", ".png", ".ply2", ".ply",
      ".geom", ".cgns", ".csv", ".pch"};
  const std::string ext = lowerExtension(path);
  if (ext == ".geo") return true;
  if (formats.count(ext)) return false;
  std::ifstream in(path, std::ios::binary);
  char head[12] = {};
  in.read(head, sizeof head);
  const std::string start(head, static_cast<std::size_t>(in.gcount()));
  for (const char* mesh : {"$PTS", "$NO", "$PARA", "$ELM", "$MeshFormat", "$Comments", "$PostFormat", "$View"})
    if (start.rfind(mesh, 0) == 0) return false;
  return true;
}

void checkGeoScript(const std::string& path) { ScriptCheck(path).check(fs::absolute(path), 0); }

}  // namespace needlesim::mesh
