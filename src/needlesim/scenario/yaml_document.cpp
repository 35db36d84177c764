#include "needlesim/scenario/yaml_document.hpp"

#include <fmt/format.h>
#include <yaml-cpp/eventhandler.h>

#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/scenario/schema.hpp"

namespace needlesim::scenario {
namespace {

SourceLocation at(const std::string& source, const YAML::Mark& mark) {
  if (mark.is_null()) return SourceLocation{source, 0, 0};
  return SourceLocation{source, mark.line + 1, mark.column + 1};
}

std::string megabytes(std::size_t bytes) { return fmt::format("{:.1f} MB", static_cast<double>(bytes) / (1 << 20)); }

void checkSize(std::size_t bytes, const std::string& source, const std::string& what) {
  if (bytes <= kMaxYamlBytes) return;
  throw InputError(SourceLocation{source, 0, 0}, "", "",
                   fmt::format("is {}, larger than the {} a YAML input may be", megabytes(bytes),
                               megabytes(kMaxYamlBytes)),
                   what + " of at most " + megabytes(kMaxYamlBytes) +
                       " (measured data and paths go in CSV files that it names)");
}

void checkUtf8(std::string_view text, const std::string& source) {
  const std::size_t bad = utf8ErrorOffset(text);
  if (bad == std::string_view::npos) return;
  const std::size_t lineStart = text.rfind('\n', bad) == std::string_view::npos ? 0 : text.rfind('\n', bad) + 1;
  std::size_t lineEnd = text.find('\n', bad);
  if (lineEnd == std::string_view::npos) lineEnd = text.size();
  int line = 1;
  for (std::size_t i = 0; i < lineStart; ++i) line += text[i] == '\n';
  const int byte = static_cast<int>(bad - lineStart) + 1;
  throw InputError(SourceLocation{source, line, byte}, "", std::string(text.substr(lineStart, lineEnd - lineStart)),
                   fmt::format("the file is not UTF-8: byte {} of line {} (0x{:02X}) is not part of a UTF-8 character; "
                               "save it as UTF-8",
                               byte, line, static_cast<unsigned char>(text[bad])),
                   "UTF-8 text (Latin-1 and UTF-16 files must be saved as UTF-8)");
}

// YAML's own tags (explicit ones such as !!str) and the non-specific ones of untagged nodes.
bool knownTag(const std::string& tag) {
  static const std::vector<std::string> ok{"",
                                           "?",
                                           "!",
                                           "tag:yaml.org,2002:str",
                                           "tag:yaml.org,2002:int",
                                           "tag:yaml.org,2002:float",
                                           "tag:yaml.org,2002:bool",
                                           "tag:yaml.org,2002:null",
                                           "tag:yaml.org,2002:map",
                                           "tag:yaml.org,2002:seq"};
  for (const auto& t : ok)
    if (t == tag) return true;
  return false;
}

// Walks the parser's events (aliases are not expanded) and refuses an unknown tag, a key
// given twice in one mapping, or (with a root section type) a key the schema does not know,
// as Section would, but as soon as the parser reaches it rather than after the whole file.
class StructureCheck : public YAML::EventHandler {
 public:
  StructureCheck(std::string source, std::string root_type)
      : source_(std::move(source)), root_type_(std::move(root_type)) {}

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override { node(mark, "", nullptr); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override { node(mark, "", nullptr); }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t, const std::string& value) override {
    node(mark, tag, &value);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {
    const Begun b = node(mark, tag, nullptr);
    frames_.push_back(Frame{false, true, {}, b.path, {}, 0, b.list_of});
  }
  void OnSequenceEnd() override { frames_.pop_back(); }
  void OnMapStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t, YAML::EmitterStyle::value) override {
    const Begun b = node(mark, tag, nullptr);
    frames_.push_back(Frame{true, true, {}, b.path, {}, 0, b.section});
  }
  void OnMapEnd() override { frames_.pop_back(); }

 private:
  struct Frame {
    bool map;
    bool expecting_key;               // in a map: the next node is a key
    std::map<std::string, int> keys;  // key -> line where it was given
    std::string path;                 // field path of the container, e.g. tissue.layers[0]
    std::string key;                  // in a map: the key of the value that comes next
    std::size_t index;                // in a sequence: the index of the next entry
    std::string type;                 // schema section type of a map, element type of a sequence; "" = free
  };
  struct Begun {
    std::string path;
    std::string section;  // the schema section type a map here would have
    std::string list_of;  // the section type of the entries a sequence here would have
  };

  // A node begins: as a key of the enclosing map, or as a value.
  Begun node(const YAML::Mark& mark, const std::string& tag, const std::string* scalar) {
    const bool isKey = !frames_.empty() && frames_.back().map && frames_.back().expecting_key;
    Begun b = isKey ? Begun{frames_.back().path, {}, {}} : value();
    if (!knownTag(tag))
      throw InputError(at(source_, mark), b.path, tag, "has an unknown tag",
                       "plain YAML without tags (or YAML's own, such as !!str)");
    if (frames_.empty()) return b;
    Frame& f = frames_.back();
    if (!f.map) ++f.index;
    if (f.map) f.expecting_key = !f.expecting_key;
    if (isKey) f.key = scalar ? *scalar : std::string("?");
    if (isKey && scalar) checkKey(f, mark, *scalar);
    return b;
  }

  void checkKey(Frame& f, const YAML::Mark& mark, const std::string& key) {
    const std::string path = f.path.empty() ? key : f.path + "." + key;
    if (!f.type.empty() && !findField(f.type, key)) throw unknownFieldError(at(source_, mark), path, key, f.type);
    const int line = mark.line + 1;
    auto [it, fresh] = f.keys.emplace(key, line);
    if (!fresh)
      throw InputError(at(source_, mark), path, "",
                       fmt::format("key '{}' given twice (lines {} and {})", printable(key), it->second, line),
                       "each key once in a section: remove one of them");
  }

  // The field path and schema types of the value that begins next (before node() advances the frame).
  Begun value() const {
    if (frames_.empty()) return Begun{"", root_type_, {}};
    const Frame& f = frames_.back();
    if (!f.map) return Begun{fmt::format("{}[{}]", f.path, f.index), f.type, {}};
    Begun b{f.path.empty() ? f.key : f.path + "." + f.key, {}, {}};
    const FieldDoc* doc = f.type.empty() ? nullptr : findField(f.type, f.key);
    if (doc && (doc->kind == Kind::Section || doc->kind == Kind::MaterialRef)) b.section = doc->child;
    if (doc && doc->kind == Kind::List) b.list_of = doc->child;
    return b;
  }

  // The field path of the value that begins next (before node() advances the frame).
  std::string childPath() const {
    if (frames_.empty()) return "";
    const Frame& f = frames_.back();
    if (!f.map) return fmt::format("{}[{}]", f.path, f.index);
    return f.path.empty() ? f.key : f.path + "." + f.key;
  }

  std::string source_;
  std::string root_type_;
  std::vector<Frame> frames_;
};

// Refuses a second document (text after a '---' that follows the first one).
class SecondDocument : public YAML::EventHandler {
 public:
  std::optional<YAML::Mark> start;
  void OnDocumentStart(const YAML::Mark& mark) override {
    if (!start) start = mark;
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override { first(mark); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override { first(mark); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t, const std::string&) override { first(mark); }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    first(mark);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    first(mark);
  }
  void OnMapEnd() override {}

 private:
  void first(const YAML::Mark& mark) {
    if (!start || start->is_null()) start = mark;
  }
};

// Collects the scalar keys of the top-level mapping; stops the parse (throws Enough) at a key
// of `enough` or after `max_keys` keys.
class TopLevelKeys : public YAML::EventHandler {
 public:
  struct Enough {};
  TopLevelKeys(const std::set<std::string>& enough, std::size_t max_keys) : enough_(enough), max_keys_(max_keys) {}
  std::set<std::string> keys;
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override { begin(nullptr); }
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override { begin(nullptr); }
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string& value) override {
    begin(&value);
  }
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    begin(nullptr);
    ++depth_;
  }
  void OnSequenceEnd() override { --depth_; }
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    begin(nullptr);
    ++depth_;
  }
  void OnMapEnd() override { --depth_; }

 private:
  void begin(const std::string* scalar) {
    if (depth_ != 1) return;
    if (expecting_key_ && scalar) keys.insert(*scalar);
    expecting_key_ = !expecting_key_;
    if (scalar && enough_.count(*scalar)) throw Enough{};
    if (keys.size() >= max_keys_) throw Enough{};
  }
  const std::set<std::string>& enough_;
  std::size_t max_keys_;
  int depth_ = 0;
  bool expecting_key_ = true;
};

InputError notYaml(const YAML::Exception& e, const std::string& source, const std::string& what) {
  return InputError(at(source, e.mark), "", "", "is not valid YAML: " + e.msg,
                    "YAML 'key: value' sections (" + what + ")");
}

}  // namespace

std::set<std::string> topLevelKeys(std::string_view text, const std::set<std::string>& enough, std::size_t max_keys) {
  std::istringstream in{std::string(text)};
  YAML::Parser parser(in);
  TopLevelKeys handler(enough, max_keys);
  try {
    parser.HandleNextDocument(handler);
  } catch (const TopLevelKeys::Enough&) {
  }
  return handler.keys;
}

std::string readYamlFile(const std::filesystem::path& path, const std::string& what) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  if (!ec) checkSize(static_cast<std::size_t>(bytes), path.string(), what);
  const auto cannot = [&](const std::string& why) {
    return InputError(SourceLocation{path.string(), 0, 0}, "", "", why, what);
  };
  if (std::filesystem::is_directory(path, ec)) throw cannot("is a folder, not a file");
  if (!std::filesystem::exists(path, ec)) throw cannot("does not exist");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw cannot("cannot be opened for reading (permissions?)");
  // read at most one byte past the limit: a device or a pipe that never ends is refused by size
  std::string text;
  char chunk[1 << 16];
  while (in && text.size() <= kMaxYamlBytes) {
    in.read(chunk, sizeof chunk);
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
  }
  checkSize(text.size(), path.string(), what);
  return text;
}

YAML::Node loadYamlDocument(std::string_view text, const std::string& source, const std::string& what,
                            const std::string& root_type) {
  checkSize(text.size(), source, what);
  checkUtf8(text, source);
  const std::string owned(text);
  try {
    std::istringstream in(owned);
    YAML::Parser parser(in);
    StructureCheck structure(source, root_type);
    parser.HandleNextDocument(structure);
    SecondDocument second;
    if (parser.HandleNextDocument(second))
      throw InputError(at(source, second.start.value_or(YAML::Mark::null_mark())), "", "",
                       "holds a second YAML document (after a '---' line)",
                       "one document: " + what + " per file (remove the '---' and what follows, or split the file)");
    return YAML::Load(owned);
  } catch (const YAML::Exception& e) {
    throw notYaml(e, source, what);
  }
}

}  // namespace needlesim::scenario
