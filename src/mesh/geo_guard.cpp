// check_untrusted_geo: a token scan of the .geo text (comments and quoted text as gmsh's own
// lexer reads them), then a look at each command word and each quoted path. gmsh reads most
// commands (SystemCall, Include, Save, ...) as plain words compared by name in its grammar,
// so words are what is checked here.
#include "mesh/geo_guard.hpp"

#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "common/error.hpp"
#include "mesh/msh_prescan.hpp"

namespace hs {
namespace {

namespace fs = std::filesystem;

struct Token {
  enum Kind { kWord, kText, kSymbol } kind;
  std::string text;
  int line;
};

bool word_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// Words, quoted texts ("..." or '...', no escapes, may span lines) and one-character
// symbols; numbers, whitespace and comments (// and /* */) are dropped.
std::vector<Token> tokenize(const std::string& s) {
  std::vector<Token> out;
  int line = 1;
  size_t i = 0;
  auto count_lines = [&](size_t from, size_t to) {
    for (size_t k = from; k < to && k < s.size(); ++k) line += s[k] == '\n';
  };
  while (i < s.size()) {
    const char c = s[i];
    const char next = i + 1 < s.size() ? s[i + 1] : '\0';
    if (std::isspace(static_cast<unsigned char>(c))) {
      line += c == '\n';
      ++i;
    } else if (c == '/' && next == '/') {
      while (i < s.size() && s[i] != '\n') ++i;
    } else if (c == '/' && next == '*') {
      const size_t end = s.find("*/", i + 2);
      const size_t stop = end == std::string::npos ? s.size() : end + 2;
      count_lines(i, stop);
      i = stop;
    } else if (c == '"' || c == '\'') {
      const size_t end = s.find(c, i + 1);
      const size_t stop = end == std::string::npos ? s.size() : end;
      out.push_back({Token::kText, s.substr(i + 1, stop - i - 1), line});
      count_lines(i, stop);
      i = stop + 1;
    } else if (word_start(c)) {
      const size_t start = i;
      while (i < s.size() && word_char(s[i])) ++i;
      out.push_back({Token::kWord, s.substr(start, i - start), line});
    } else if (std::isdigit(static_cast<unsigned char>(c)) ||
               (c == '.' && std::isdigit(static_cast<unsigned char>(next)))) {
      while (i < s.size() && (std::isdigit(static_cast<unsigned char>(s[i])) || s[i] == '.')) ++i;
      if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
        while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
      }
    } else {
      out.push_back({Token::kSymbol, std::string(1, c), line});
      ++i;
    }
  }
  return out;
}

const std::set<std::string> kRunsCommands = {"SystemCall", "NonBlockingSystemCall", "System",
                                             "OnelabRun", "OnelabAction"};
const std::set<std::string> kEndsProcess = {"Exit", "Abort"};
const std::set<std::string> kReadsInput = {"GetValue", "GetStringValue"};
const std::set<std::string> kWritesFiles = {"Save", "Print", "CreateDir", "DeleteFile",
                                            "RenameFile"};
const std::set<std::string> kReadsFiles = {"Include", "Merge",         "MergeWithBoundingBox",
                                           "Open",    "ShapeFromFile", "ListFromFile"};

// Options that name a file gmsh writes or a program it starts.
bool option_names_file_or_program(const std::string& category, const std::string& name) {
  return category == "Solver" || name.find("FileName") != std::string::npos ||
         name.find("Executable") != std::string::npos || name == "SaveOptions" ||
         name == "SaveSession";
}

// How gmsh's MergeFile reads a file (the Merge, Open and MergeWithBoundingBox commands, and
// gmsh::open): by its extension where it knows it, in exactly lower or upper case; a file of
// any other extension by its first line: a mesh when that begins as one, a script otherwise.
enum class GmshReads { kScript, kMesh, kCad, kUncompress, kOther };

GmshReads gmsh_reads(const fs::path& path) {
  const std::string ext = path.extension().string();
  std::string lower = ext, upper = ext;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (ext == lower || ext == upper) {
    if (lower == ".gz") return GmshReads::kUncompress;
    for (const char* cad : {".step", ".stp", ".brep", ".brp", ".rle", ".iges", ".igs"})
      if (lower == cad) return GmshReads::kCad;
    for (const char* other :
         {".stl",  ".sat",  ".unv",  ".vtk", ".wrl", ".vrml", ".iv",  ".mesh", ".diff",
          ".med",  ".mmed", ".rmed", ".bdf", ".nas", ".dat",  ".p3d", ".fm",   ".pnm",
          ".pbm",  ".pgm",  ".ppm",  ".bmp", ".jpg", ".jpeg", ".png", ".ply2", ".ply",
          ".geom", ".cgns", ".csv",  ".py",  ".m",   ".exe",  ".pro"})
      if (lower == other) return GmshReads::kOther;
  }
  std::ifstream in(path, std::ios::binary);
  char first[256] = {};
  in.read(first, sizeof first - 1);
  const std::string line(first, static_cast<size_t>(in.gcount()));
  for (const char* mesh : {"$PTS", "$NO", "$PARA", "$ELM", "$MeshFormat", "$Comments"})
    if (line.compare(0, std::strlen(mesh), mesh) == 0) return GmshReads::kMesh;
  if (line.compare(0, 11, "$PostFormat") == 0 || line.compare(0, 5, "$View") == 0)
    return GmshReads::kOther;
  return GmshReads::kScript;
}

class GeoGuard {
 public:
  explicit GeoGuard(const std::vector<std::string>& allowed_dirs) {
    for (const auto& dir : allowed_dirs)
      if (!dir.empty()) allowed_.push_back(resolved(fs::path(dir)));
  }

  // A file gmsh merges (gmsh::open, and a .geo's Merge or Open), checked as gmsh will read it;
  // `where`, `command` and `line` place the command that merges it in messages.
  void merged(const std::string& file, int depth, const std::string& where,
              const std::string& command, int line) {
    switch (gmsh_reads(fs::path(file))) {
      case GmshReads::kScript:
        check(file, depth);
        break;
      case GmshReads::kMesh:
        prescan_msh(file);
        break;
      case GmshReads::kCad:
        break;
      case GmshReads::kUncompress:
        fail(where, command, "gmsh uncompresses a .gz file with a shell command", line);
      case GmshReads::kOther:
        fail(where, command,
             "gmsh would read it as neither a .geo script, a .msh mesh nor a CAD file (STEP, "
             "BREP, IGES), the only files a .geo may merge",
             line);
    }
    options_of(file, depth);
  }

  // After every file it merges, gmsh merges "<file>.opt" too, unasked, when one lies beside it.
  void options_of(const std::string& file, int depth) {
    std::error_code error;
    const std::string options = file + ".opt";
    if (fs::is_regular_file(options, error)) merged(options, depth + 1, options, "", 0);
  }

  void check(const std::string& file, int depth) {
    const fs::path here = resolved(fs::path(file));
    if (!visited_.insert(here.string()).second) return;  // included twice, or a cycle
    if (depth > kMaxDepth) fail(file, "Include", "includes nest deeper than 16 files", 1);
    std::ifstream in(file);
    if (!in) throw InputError(file + ": cannot open the .geo file (missing or unreadable)");
    std::ostringstream text;
    text << in.rdbuf();
    const std::vector<Token> tokens = tokenize(text.str());
    // gmsh reads a relative name from the folder of the name it was given (a link's own).
    const fs::path folder = fs::absolute(fs::path(file)).parent_path();
    for (size_t i = 0; i < tokens.size(); ++i) check_token(file, folder, tokens, i, depth);
  }

 private:
  static constexpr int kMaxDepth = 16;

  [[noreturn]] static void fail(const std::string& file, const std::string& what,
                                const std::string& reason, int line) {
    throw InputError(file + ": " + what + ": " + reason +
                     "; refused in a .geo that the deck does not trust (mesh.trust_geo) (line " +
                     std::to_string(line) + ")");
  }

  // The absolute path with ".." and symbolic links resolved as far as it exists.
  static fs::path resolved(const fs::path& p) {
    std::error_code error;
    fs::path r = fs::weakly_canonical(fs::absolute(p), error);
    return error ? fs::absolute(p).lexically_normal() : r;
  }

  bool allowed(const fs::path& p) const {
    for (const auto& dir : allowed_) {
      auto d = dir.begin(), q = p.begin();
      for (; d != dir.end() && q != p.end() && *d == *q; ++d, ++q) {
      }
      if (d == dir.end() || (std::next(d) == dir.end() && d->empty())) return true;
    }
    return false;
  }

  // A quoted text as gmsh would read it as a file name: relative to the .geo's own folder.
  // Empty when it does not resolve (a '~', a NUL), which counts as outside.
  fs::path as_path(const fs::path& folder, const std::string& text) const {
    if (text.empty() || text[0] == '~' || text.find('\0') != std::string::npos) return {};
    const fs::path p(text);
    return resolved(p.is_absolute() ? p : folder / p);
  }

  static bool looks_like_path(const std::string& text) {
    return text.find('/') != std::string::npos || text.find('\\') != std::string::npos ||
           (!text.empty() && text[0] == '~') || text == "..";
  }

  void check_token(const std::string& file, const fs::path& folder, const std::vector<Token>& t,
                   size_t i, int depth) {
    const Token& token = t[i];
    if (token.kind == Token::kText) {
      if (looks_like_path(token.text)) {
        const fs::path p = as_path(folder, token.text);
        if (p.empty() || !allowed(p))
          fail(file, "\"" + token.text + "\"",
               "names a file outside the .geo's folder and the deck's folder", token.line);
      }
      return;
    }
    if (token.kind != Token::kWord) return;
    const bool option = i >= 2 && t[i - 1].text == "." && t[i - 2].kind == Token::kWord;
    if (option) {
      if (option_names_file_or_program(t[i - 2].text, token.text))
        fail(file, t[i - 2].text + "." + token.text, "an option that names a file or a program",
             token.line);
      return;
    }
    const std::string& w = token.text;
    if (kRunsCommands.count(w)) fail(file, w, "runs a shell command or a program", token.line);
    if (kEndsProcess.count(w)) fail(file, w, "ends the whole process", token.line);
    if (kWritesFiles.count(w)) fail(file, w, "writes or removes files", token.line);
    if (kReadsInput.count(w)) fail(file, w, "reads an answer from standard input", token.line);
    if (w == "Printf") check_printf(file, t, i);
    if (kReadsFiles.count(w)) check_read(file, folder, t, i, depth);
  }

  // Printf("...", ...) > "file" (or >>) writes to a file; plain Printf only prints.
  static void check_printf(const std::string& file, const std::vector<Token>& t, size_t i) {
    size_t k = i + 1;
    if (k >= t.size() || t[k].text != "(") return;
    int open = 0;
    for (; k < t.size(); ++k) {
      if (t[k].kind != Token::kSymbol) continue;
      open += t[k].text == "(" ? 1 : t[k].text == ")" ? -1 : 0;
      if (open == 0) break;
    }
    if (k + 1 < t.size() && t[k + 1].kind == Token::kSymbol && t[k + 1].text == ">")
      fail(file, "Printf", "writes to a file (Printf(...) > file)", t[i].line);
  }

  // The file read must be written out as one quoted text, inside the allowed folders; a
  // .geo read that way is checked in turn.
  void check_read(const std::string& file, const fs::path& folder, const std::vector<Token>& t,
                  size_t i, int depth) {
    size_t k = i + 1;
    if (k < t.size() && t[k].text == "(") ++k;
    const bool literal = k < t.size() && t[k].kind == Token::kText &&
                         (k + 1 == t.size() || t[k + 1].text == ";" || t[k + 1].text == ")");
    const std::string& w = t[i].text;
    if (!literal)
      fail(file, w, "reads a file whose name is computed, which cannot be checked before meshing",
           t[i].line);
    const fs::path p = as_path(folder, t[k].text);
    if (p.empty() || !allowed(p))
      fail(file, w + " \"" + t[k].text + "\"",
           "reads a file outside the .geo's folder and the deck's folder", t[i].line);
    std::error_code error;  // a name too long for the system: gmsh will not find it either
    if (!fs::is_regular_file(p, error)) return;
    if (w == "Include")  // parsed as a script, whatever its name
      check(p.string(), depth + 1);
    else if (w == "ShapeFromFile") {
      if (gmsh_reads(p) != GmshReads::kCad)
        fail(file, w + " \"" + t[k].text + "\"", "imports CAD files only (STEP, BREP, IGES)",
             t[i].line);
    } else if (w != "ListFromFile") {  // ListFromFile reads numbers only
      merged(p.string(), depth + 1, file, w + " \"" + t[k].text + "\"", t[i].line);
    }
  }

  std::vector<fs::path> allowed_;
  std::set<std::string> visited_;
};

}  // namespace

void check_untrusted_geo(const std::string& file, const std::vector<std::string>& allowed_dirs) {
  std::vector<std::string> dirs = allowed_dirs;
  dirs.push_back(fs::absolute(fs::path(file)).parent_path().string());
  GeoGuard(dirs).merged(file, 0, file, "", 0);
}

void check_untrusted_msh(const std::string& file, const std::vector<std::string>& allowed_dirs) {
  if (gmsh_reads(fs::path(file)) != GmshReads::kMesh)
    throw InputError(file +
                     ": its first line is not $MeshFormat (nor another that a .msh begins with): "
                     "gmsh would run the file as a .geo script");
  std::vector<std::string> dirs = allowed_dirs;
  dirs.push_back(fs::absolute(fs::path(file)).parent_path().string());
  GeoGuard(dirs).options_of(file, 0);
}

}  // namespace hs
