#include "json_locations.h"

#include <iterator>
#include <set>
#include <vector>

namespace caustix::bake {
namespace {

// An input iterator over the text that publishes how far the lexer has read,
// so SAX callbacks can tell where they are.
struct TrackingIterator {
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  const char* p = nullptr;
  const char** furthest = nullptr;

  reference operator*() const { return *p; }
  TrackingIterator& operator++() {
    ++p;
    if (p > *furthest) *furthest = p;
    return *this;
  }
  TrackingIterator operator++(int) { auto t = *this; ++*this; return t; }
  bool operator==(const TrackingIterator& o) const { return p == o.p; }
};

class LocatingHandler {
 public:
  using json = nlohmann::json;
  using number_integer_t = json::number_integer_t;
  using number_unsigned_t = json::number_unsigned_t;
  using number_float_t = json::number_float_t;
  using string_t = json::string_t;
  using binary_t = json::binary_t;

  LocatingHandler(const std::string& text, const char** furthest, LocatedJson& out)
      : text_(text), furthest_(furthest), out_(out), dom_(out.root, /*allow_exceptions=*/false) {}

  bool null() { element(); return dom_.null(); }
  bool boolean(bool v) { element(); return dom_.boolean(v); }
  bool number_integer(number_integer_t v) { element(); return dom_.number_integer(v); }
  bool number_unsigned(number_unsigned_t v) { element(); return dom_.number_unsigned(v); }
  bool number_float(number_float_t v, const string_t& s) { element(); return dom_.number_float(v, s); }
  bool string(string_t& v) { element(); return dom_.string(v); }
  bool binary(binary_t& v) { element(); return dom_.binary(v); }

  bool start_object(std::size_t n) {
    element();
    frames_.push_back(Frame{false, 0, path_of_value(), {}, {}});
    return dom_.start_object(n);
  }
  bool key(string_t& k) {
    const std::size_t start = token_start();
    Frame& f = frames_.back();
    if (!f.keys.insert(k).second) {
      duplicate_ = "duplicate key \"" + k + "\"";
      duplicate_pos_ = position(start);
      return false;
    }
    f.key = k;
    out_.positions[f.path + "/" + pointer_token(k)] = position(start);
    mark();
    return dom_.key(k);
  }
  bool end_object() { frames_.pop_back(); mark(); return dom_.end_object(); }
  bool start_array(std::size_t n) {
    element();
    frames_.push_back(Frame{true, 0, path_of_value(), {}, {}});
    return dom_.start_array(n);
  }
  bool end_array() { frames_.pop_back(); mark(); return dom_.end_array(); }

  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& ex) {
    // nlohmann's message reads "[json.exception.parse_error.101] parse error
    // at line L, column C: ..."; keep the part from "line".
    std::string msg = ex.what();
    const auto at = msg.find("at line ");
    out_.error = at == std::string::npos ? msg : msg.substr(at + 3);
    return false;
  }

  bool failed_on_duplicate(std::string& msg) const {
    if (duplicate_.empty()) return false;
    msg = "line " + std::to_string(duplicate_pos_.line) + ", column " +
          std::to_string(duplicate_pos_.column) + ": " + duplicate_;
    return true;
  }

 private:
  struct Frame {
    bool is_array;
    std::size_t index;
    std::string path;
    std::string key;
    std::set<std::string> keys;
  };

  // Path of the value being started: the array element or the member.
  std::string path_of_value() const {
    if (frames_.empty()) return "";
    const Frame& f = frames_.back();
    if (f.is_array) return f.path + "/" + std::to_string(f.index - 1);
    return f.path + "/" + pointer_token(f.key);
  }

  // Called at the start of every value: array elements get a position.
  void element() {
    const std::size_t start = token_start();
    if (!frames_.empty() && frames_.back().is_array) {
      Frame& f = frames_.back();
      out_.positions[f.path + "/" + std::to_string(f.index)] = position(start);
      ++f.index;
    }
    mark();
  }

  // Between two events there are only separators and whitespace, so the
  // current token starts at the first other character after the last event
  // (the lexer may have read one character ahead; that is a separator).
  std::size_t token_start() const {
    std::size_t i = last_;
    while (i < text_.size() && (text_[i] == ' ' || text_[i] == '\t' || text_[i] == '\n' ||
                                text_[i] == '\r' || text_[i] == ',' || text_[i] == ':')) {
      ++i;
    }
    return i;
  }
  void mark() { last_ = static_cast<std::size_t>(*furthest_ - text_.data()); }

  SourcePos position(std::size_t offset) const {
    // Line/column on demand; scene files are small.
    SourcePos p;
    for (std::size_t i = 0; i < offset && i < text_.size(); ++i) {
      if (text_[i] == '\n') { ++p.line; p.column = 1; } else { ++p.column; }
    }
    return p;
  }

  const std::string& text_;
  const char** furthest_;
  LocatedJson& out_;
  nlohmann::detail::json_sax_dom_parser<nlohmann::json> dom_;
  std::vector<Frame> frames_;
  std::size_t last_ = 0;
  std::string duplicate_;
  SourcePos duplicate_pos_;
};

}  // namespace

std::string pointer_token(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

LocatedJson parse_located_json(const std::string& text) {
  LocatedJson out;
  const char* furthest = text.data();
  LocatingHandler handler(text, &furthest, out);
  TrackingIterator first{text.data(), &furthest};
  TrackingIterator last{text.data() + text.size(), &furthest};
  bool ok = false;
  try {
    ok = nlohmann::json::sax_parse(first, last, &handler);
  } catch (const std::exception& e) {  // e.g. allocation failure
    out.error = e.what();
    return out;
  }
  if (!ok && out.error.empty() && !handler.failed_on_duplicate(out.error)) {
    out.error = "invalid JSON";
  }
  return out;
}

}  // namespace caustix::bake
