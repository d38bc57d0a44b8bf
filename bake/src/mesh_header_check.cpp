// Element counts a PLY or binary STL header declares, checked against the
// data before a library reads the file (mesh_soup.h). The readers size
// containers from these counts and from every list length in the data
// (10^9 declared vertices, or one face claiming 2^31 corners: an allocation
// that fails or exhausts memory), and say nothing about where a file is
// wrong. So this walks the PLY's layout as its header describes it -- each
// element's properties, each list's length -- only far enough to prove that
// the data holds what the header declares, and names the element, its index
// and the line or byte where it does not. (OFF's counts are bounded the same
// way in read_off, where CGAL's scanner has parsed the header.)

#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

#include "mesh_soup.h"

namespace caustix::bake {
namespace {

struct PlyProperty {
  std::string name;
  std::string type;         // of a scalar, or of a list's items
  int size = 0;             // bytes of a scalar, or of a list's items
  int count_size = 0;       // bytes of a list's length; 0 for a scalar
  bool count_signed = false;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

// PLY's scalar types and their sizes (both the classic and the sized names).
int ply_type_size(std::string_view t, bool* is_signed = nullptr) {
  static const std::array<std::pair<std::string_view, int>, 16> types{{{"char", -1}, {"uchar", 1}, {"int8", -1},
      {"uint8", 1}, {"short", -2}, {"ushort", 2}, {"int16", -2}, {"uint16", 2}, {"int", -4}, {"uint", 4},
      {"int32", -4}, {"uint32", 4}, {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}}};
  for (const auto& [name, size] : types) {
    if (t == name) {
      if (is_signed) *is_signed = size < 0 || name.find("float") == 0 || name == "double";
      return size < 0 ? -size : size;
    }
  }
  return 0;
}

std::string declared(const PlyElement& e) { return std::to_string(e.count) + " '" + e.name + "' elements"; }

// What CGAL's PLY reader can read (CGAL/IO/PLY.h, PLY_reader.h): it takes
// a vertex's x, y, z as float or double (any other type it dereferences as
// a null pointer: found by fuzz_mesh_import) and a missing one as 0, and a
// face's corners from a vertex_indices or vertex_index list of int or uint.
// Normals of another type are reported in `normals` (read_ply skips them
// with a warning).
std::optional<std::string> check_ply_types(const std::vector<PlyElement>& elements, PlyNormals& normals) {
  const auto readable = [](const PlyProperty& p) {
    return p.count_size == 0 && (p.type.rfind("float", 0) == 0 || p.type == "double");
  };
  const auto find = [](const PlyElement& e, std::string_view name) -> const PlyProperty* {
    for (const PlyProperty& p : e.properties) {
      if (p.name == name) return &p;
    }
    return nullptr;
  };
  for (const PlyElement& e : elements) {
    if (e.name == "vertex" || e.name == "vertices") {
      for (const char* axis : {"x", "y", "z"}) {
        const PlyProperty* p = find(e, axis);
        if (!p) return "the '" + e.name + "' element has no '" + axis + "' property";
        if (!readable(*p)) {
          return "the '" + e.name + "' property '" + axis + "' is " + (p->count_size ? "a list of " : "") + p->type +
                 "; coordinates must be float or double (what CGAL's PLY reader reads)";
        }
      }
      for (const char* axis : {"nx", "ny", "nz"}) {
        const PlyProperty* p = find(e, axis);
        if (!p) continue;
        normals.present = true;
        if (!readable(*p) && normals.unreadable_type.empty()) {
          normals.unreadable_type = p->count_size ? "list of " + p->type : p->type;
        }
      }
    } else if (e.name == "face" || e.name == "faces") {
      const PlyProperty* p = find(e, "vertex_indices");
      if (!p) p = find(e, "vertex_index");
      if (!p) return "the '" + e.name + "' element has no vertex_indices (or vertex_index) list";
      if (p->count_size == 0 || (p->type != "int" && p->type != "int32" && p->type != "uint" && p->type != "uint32")) {
        return "the '" + e.name + "' property '" + p->name + "' is " + (p->count_size ? "a list of " : "") + p->type +
               "; it must be a list of int or uint (what CGAL's PLY reader reads)";
      }
    }
  }
  return std::nullopt;
}

std::optional<std::string> check_ply(std::ifstream& in, std::uint64_t file_size, PlyNormals& normals) {
  std::string line, format;
  std::vector<PlyElement> elements;
  std::size_t line_no = 0;
  bool magic = false, ended = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (line_no == 1) {
      magic = word == "ply";
      if (!magic) return std::string("not a PLY file: the first line is not 'ply'");
      continue;
    }
    if (word == "format") {
      ls >> format;
    } else if (word == "element") {
      PlyElement e;
      long double n = -1;
      ls >> e.name >> n;
      if (!ls || n < 0 || n > 1e18L) return "header line " + std::to_string(line_no) + ": bad element count";
      e.count = static_cast<std::uint64_t>(n);
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) return "header line " + std::to_string(line_no) + ": a property before any element";
      PlyProperty p;
      std::string type;
      ls >> type;
      if (type == "list") {
        std::string count_t, item_t;
        ls >> count_t >> item_t >> p.name;
        p.count_size = ply_type_size(count_t, &p.count_signed);
        p.size = ply_type_size(item_t);
        p.type = item_t;
        if (p.count_size == 0 || p.size == 0) {
          return "header line " + std::to_string(line_no) + ": unknown list type '" + count_t + " " + item_t + "'";
        }
      } else {
        ls >> p.name;
        p.size = ply_type_size(type);
        p.type = type;
        if (p.size == 0) return "header line " + std::to_string(line_no) + ": unknown property type '" + type + "'";
      }
      elements.back().properties.push_back(p);
    } else if (word == "end_header") {
      ended = true;
      break;
    }
  }
  if (!ended) return std::string("the PLY header has no end_header line");
  if (auto bad = check_ply_types(elements, normals)) return bad;
  // An element without properties takes no data, so nothing bounds its
  // count; readers still loop over its items (10^9 of them: seconds spent
  // reading nothing, found by fuzz_mesh_import). A file cannot mean more
  // such items than it has bytes.
  for (const PlyElement& e : elements) {
    if (e.properties.empty() && e.count > file_size) {
      return "the header declares " + declared(e) + " without properties: more items than the file has bytes";
    }
  }
  std::streamoff at = in.tellg();
  if (at < 0) at = static_cast<std::streamoff>(file_size);

  if (format == "ascii") {
    // Values are white-space separated; a list's length says how many of
    // the following values are its items. Lines do not matter to readers,
    // but name the place.
    std::size_t at_line = line_no + 1, tok_line = at_line;
    std::string tok;
    bool after_newline = false;  // the last value ended its line
    auto next = [&]() -> bool {
      tok.clear();
      for (char c = 0; in.get(c);) {
        if (!std::isspace(static_cast<unsigned char>(c))) {
          tok.push_back(c);
          break;
        }
        at_line += c == '\n';
      }
      if (tok.empty()) return false;
      tok_line = at_line;
      after_newline = true;  // unless a separator other than a newline follows
      for (char c = 0; in.get(c);) {
        if (std::isspace(static_cast<unsigned char>(c))) {
          at_line += c == '\n';
          after_newline = c == '\n';
          break;
        }
        tok.push_back(c);
      }
      return true;
    };
    const auto at_item = [&](const PlyElement& e, std::uint64_t i) {
      return "'" + e.name + "' " + std::to_string(i) + " (line " + std::to_string(tok_line) + ")";
    };
    // Writers put one element on a line. Where an element's values end
    // before its line does, a later failure is most likely this one's:
    // the first such place is named along with the failure.
    std::string misaligned;
    const auto ends_line = [&] {
      if (after_newline) return true;
      while (in.peek() == ' ' || in.peek() == '\t' || in.peek() == '\r') in.get();
      return in.peek() == '\n' || in.peek() == std::char_traits<char>::eof();
    };
    const auto fail = [&](std::string msg) {
      if (!misaligned.empty()) msg += "; the data stops matching the header earlier: " + misaligned;
      return msg;
    };
    for (const PlyElement& e : elements) {
      for (std::uint64_t i = 0; i < e.count && !e.properties.empty(); ++i) {
        for (const PlyProperty& p : e.properties) {
          if (!next()) return fail("the header declares " + declared(e) + ", but the data ends in " + at_item(e, i));
          double v = 0;
          const char* first = tok.data() + (tok[0] == '+' ? 1 : 0);
          const auto parsed = std::from_chars(first, tok.data() + tok.size(), v);
          if (parsed.ec != std::errc() || parsed.ptr != tok.data() + tok.size()) {
            return fail(at_item(e, i) + ": '" + tok + "' is not a number");
          }
          if (p.count_size == 0) continue;
          if (!(v >= 0 && v == std::floor(v) && v <= 1e9)) return fail(at_item(e, i) + ": list '" + p.name + "' has length " + tok);
          for (std::uint64_t k = 0; k < static_cast<std::uint64_t>(v); ++k) {
            if (!next()) {
              return fail("the header declares " + declared(e) + ", but the data ends inside list '" + p.name + "' of " +
                          at_item(e, i));
            }
          }
        }
        if (misaligned.empty() && !e.properties.empty() && !ends_line()) {
          misaligned = at_item(e, i) + " has more values on its line than the header's properties take";
        }
      }
    }
    if (next()) {
      return fail("the header declares " + std::to_string(elements.size()) +
                  " element types, but more values follow their data (line " + std::to_string(tok_line) + ")");
    }
    return std::nullopt;
  }

  const bool big = format == "binary_big_endian";
  if (!big && format != "binary_little_endian") return "unknown PLY format '" + format + "'";
  auto pos = static_cast<std::uint64_t>(at);
  auto read_count = [&](const PlyProperty& p, std::uint64_t& n) -> bool {
    if (pos + static_cast<std::uint64_t>(p.count_size) > file_size) return false;
    unsigned char b[8] = {};
    in.seekg(static_cast<std::streamoff>(pos));
    in.read(reinterpret_cast<char*>(b), p.count_size);
    if (!in) return false;
    std::uint64_t u = 0;
    for (int k = 0; k < p.count_size; ++k) u |= std::uint64_t{b[big ? p.count_size - 1 - k : k]} << (8 * k);
    if (p.count_signed && (u >> (8 * p.count_size - 1)) != 0) return false;  // a negative length
    n = u;
    pos += static_cast<std::uint64_t>(p.count_size);
    return true;
  };
  for (const PlyElement& e : elements) {
    bool fixed = true;
    std::uint64_t record = 0;
    for (const PlyProperty& p : e.properties) {
      fixed = fixed && p.count_size == 0;
      record += static_cast<std::uint64_t>(p.size);
    }
    if (fixed) {  // one multiplication instead of a walk
      if (static_cast<long double>(record) * e.count > static_cast<long double>(file_size - pos)) {
        return "the header declares " + declared(e) + " of " + std::to_string(record) + " bytes each, but " +
               std::to_string(file_size - pos) + " bytes of data are left for them (from byte " + std::to_string(pos) + ")";
      }
      pos += record * e.count;
      continue;
    }
    for (std::uint64_t i = 0; i < e.count; ++i) {
      for (const PlyProperty& p : e.properties) {
        std::uint64_t n = 1;
        if (p.count_size > 0 && !read_count(p, n)) {
          return "the header declares " + declared(e) + ", but '" + e.name + "' " + std::to_string(i) +
                 " has no valid length for list '" + p.name + "' (byte " + std::to_string(pos) + ")";
        }
        const long double bytes = static_cast<long double>(n) * p.size;
        if (bytes > static_cast<long double>(file_size - pos)) {
          return "the header declares " + declared(e) + ", but the data ends in '" + e.name + "' " +
                 std::to_string(i) + " (byte " + std::to_string(pos) + ")";
        }
        pos += n * static_cast<std::uint64_t>(p.size);
      }
    }
  }
  // Trailing white space (a final newline) is harmless; anything else means
  // the header does not describe the file.
  in.clear();
  in.seekg(static_cast<std::streamoff>(pos));
  for (char c = 0; in.get(c);) {
    if (!std::isspace(static_cast<unsigned char>(c))) {
      return "the header's elements end at byte " + std::to_string(pos) + ", but the file has " +
             std::to_string(file_size) + " bytes: the header declares fewer elements than the data holds";
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> check_declared_counts(const std::string& path, MeshFormat format, PlyNormals* normals) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  const auto size = static_cast<std::uint64_t>(std::filesystem::file_size(path, ec));
  if (!in || ec) return std::string("cannot open the file");
  if (format == MeshFormat::kPly) {
    PlyNormals unused;
    return check_ply(in, size, normals ? *normals : unused);
  }
  if (format == MeshFormat::kStl) {
    char head[84] = {};
    in.read(head, sizeof head);
    if (in.gcount() < 84) return std::nullopt;  // too short for binary: ASCII or nothing (the reader decides)
    std::string start(head, 5);
    for (char& c : start) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    std::uint32_t n = 0;
    std::memcpy(&n, head + 80, 4);
    const std::uint64_t binary_size = 84 + 50 * std::uint64_t{n};
    // An ASCII STL starts with "solid" (so may a binary one's free-form
    // header: then the size decides, as CGAL's reader does).
    if (start == "solid" && binary_size != size) return std::nullopt;
    if (binary_size != size) {
      return "the header declares " + std::to_string(n) + " triangles, but the file has " + std::to_string(size) +
             " bytes (a binary STL of that many takes " + std::to_string(binary_size) + ")";
    }
  }
  return std::nullopt;
}

}  // namespace caustix::bake
