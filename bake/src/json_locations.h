#pragma once
// Parses JSON with nlohmann's SAX interface, building the DOM and, on the
// side, the source position of every object key and array element, keyed by
// JSON pointer. nlohmann's DOM keeps no positions, and scene errors must name
// line and column.

#include <nlohmann/json.hpp>

#include <map>
#include <string>

namespace caustix::bake {

struct SourcePos {
  std::size_t line = 1;    // 1-based
  std::size_t column = 1;  // 1-based, in bytes
};

struct LocatedJson {
  nlohmann::json root;
  std::map<std::string, SourcePos> positions;  // JSON pointer -> position
  std::string error;                           // syntax error ("LINE:COL: ...") or empty
};

LocatedJson parse_located_json(const std::string& text);

// Escapes a key for use as a JSON pointer token (RFC 6901).
std::string pointer_token(const std::string& key);

}  // namespace caustix::bake
