#pragma once
// Walking text held in memory: line by line (LineScanner, Fields) for the
// line-oriented formats, token by token across lines (TokenScanner) for
// ASCII PLY. Nothing is copied; every piece is a view into the file content.
//
// Both refuse, with ParseError "FILE:LINE: ...", a line longer than
// max_line_length and a NUL byte: neither occurs in a text file, and
// stopping there is what keeps a large binary or garbage file from being
// scanned to its end.

#include "io_detail.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace recon::io::detail {

/// Space, tab, carriage return, form feed, vertical tab (not newline).
[[nodiscard]] inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

[[nodiscard]] inline std::string_view trim(std::string_view text) {
  std::size_t begin = 0;
  while (begin < text.size() && is_blank(text[begin])) ++begin;
  std::size_t end = text.size();
  while (end > begin && is_blank(text[end - 1])) --end;
  return text.substr(begin, end - begin);
}

/// The line up to a comment mark ('#' for every text format here).
[[nodiscard]] inline std::string_view without_comment(std::string_view line, char mark = '#') {
  const std::size_t at = line.find(mark);
  return at == std::string_view::npos ? line : line.substr(0, at);
}

[[noreturn]] inline void fail_long_line(std::string_view file, std::size_t line) {
  fail_at_line(file, line,
               "line " + std::to_string(line) + " is longer than " + std::to_string(max_line_length) +
                   " bytes (1 MiB), the most recon reads on one line: this is not a text file of points");
}

[[noreturn]] inline void fail_nul_byte(std::string_view file, std::size_t line, std::size_t column) {
  fail_at_line(file, line,
               "a NUL byte at column " + std::to_string(column) +
                   ": this is binary data, not text (is the format or the extension wrong?)");
}

/// The length of a UTF-8 byte-order mark at the start of `text` (3), or 0.
/// Editors on Windows and some exporters begin text files with one.
[[nodiscard]] inline std::size_t byte_order_mark_length(std::string_view text) {
  return text.starts_with("\xEF\xBB\xBF") ? 3 : 0;
}

/// How the lines of a text end: '\n' (with or without '\r' before it), or
/// '\r' alone (classic Mac OS; some exporters still write it).
enum class LineEnds : std::uint8_t { newline, carriage_return };

/// True when `bytes` read as a line of text: printable ASCII, tabs and
/// well-formed UTF-8 sequences, no control character.
[[nodiscard]] inline bool looks_like_text(std::string_view bytes) {
  for (std::size_t i = 0; i < bytes.size();) {
    const auto c = static_cast<unsigned char>(bytes[i]);
    if (c == '\t' || (c >= 0x20 && c < 0x7f)) {
      ++i;
      continue;
    }
    // A UTF-8 lead byte and how many continuation bytes (10xxxxxx) follow it.
    const std::size_t follow = c >= 0xc2 && c <= 0xdf ? 1 : c >= 0xe0 && c <= 0xef ? 2 : c >= 0xf0 && c <= 0xf4 ? 3 : 0;
    if (follow == 0 || bytes.size() - i <= follow) return false;
    for (std::size_t k = 1; k <= follow; ++k)
      if ((static_cast<unsigned char>(bytes[i + k]) & 0xc0) != 0x80) return false;
    i += follow + 1;
  }
  return true;
}

/// The line ends of the text from byte `start`: carriage_return when its
/// first line end is a '\r' not followed by '\n' and the bytes before it read
/// as text (binary data holds '\r' bytes too, and must not be cut into short
/// "lines" at them); newline otherwise.
[[nodiscard]] inline LineEnds detect_line_ends(std::string_view text, std::size_t start = 0) {
  const std::string_view head = text.substr(std::min(start, text.size()), max_line_length + 1);
  const std::size_t end = head.find_first_of("\r\n");
  if (end == std::string_view::npos || head[end] == '\n') return LineEnds::newline;
  if (end + 1 < head.size() && head[end + 1] == '\n') return LineEnds::newline;
  if (end + 1 == head.size() && start + end + 1 < text.size() && text[start + end + 1] == '\n')
    return LineEnds::newline;
  return looks_like_text(head.substr(0, end)) ? LineEnds::carriage_return : LineEnds::newline;
}

/// Lines of a text, numbered from 1. With LineEnds::newline, "\n" and
/// "\r\n" end a line; with LineEnds::carriage_return, "\r" alone ends one
/// too. The last line needs no line end.
class LineScanner {
 public:
  /// Starts at byte `start`, which is the beginning of line `first_line`;
  /// `file` names the file in error messages.
  explicit LineScanner(std::string_view file, std::string_view text, std::size_t start = 0, std::size_t first_line = 1,
                       LineEnds ends = LineEnds::newline)
      : file_(file), text_(text), position_(start), line_number_(first_line - 1), ends_(ends) {}

  /// The next line without its line end; false at the end of the text.
  bool next(std::string_view& line) {
    if (position_ >= text_.size()) return false;
    const char* begin = text_.data() + position_;
    // Look for the line end no further than the longest line allowed.
    const std::size_t left = std::min(text_.size() - position_, max_line_length + 1);
    const char* end = ends_ == LineEnds::newline ? static_cast<const char*>(std::memchr(begin, '\n', left))
                                                 : find_either_line_end(begin, left);
    ++line_number_;
    if (end == nullptr && left > max_line_length) fail_long_line(file_, line_number_);
    const std::size_t length = end ? static_cast<std::size_t>(end - begin) : left;
    if (const void* nul = std::memchr(begin, '\0', length))
      fail_nul_byte(file_, line_number_, static_cast<std::size_t>(static_cast<const char*>(nul) - begin) + 1);
    position_ += length;
    if (end != nullptr) {
      ++position_;
      if (*end == '\r' && position_ < text_.size() && text_[position_] == '\n') ++position_;
    }
    line = std::string_view(begin, length);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return true;
  }

  /// Number of the line last returned by next() (0 before the first).
  [[nodiscard]] std::size_t line_number() const { return line_number_; }
  /// Byte offset just after the line last returned (where the next begins).
  [[nodiscard]] std::size_t position() const { return position_; }
  [[nodiscard]] bool at_end() const { return position_ >= text_.size(); }

 private:
  static const char* find_either_line_end(const char* begin, std::size_t size) {
    const char* end = std::find_if(begin, begin + size, [](char c) { return c == '\n' || c == '\r'; });
    return end == begin + size ? nullptr : end;
  }

  std::string_view file_;
  std::string_view text_;
  std::size_t position_;
  std::size_t line_number_;
  LineEnds ends_;
};

/// How the columns of delimited text are separated: by blanks (spaces and
/// tabs, any number of them), or by one comma or one semicolon with optional
/// blanks around it.
enum class Separator : std::uint8_t { blanks, comma, semicolon };

/// The fields of one line: separated by blanks, or by commas or semicolons
/// (delimited text). With a comma or a semicolon a field may be empty
/// ("1,,2" has three fields, the second empty); blanks around a field are
/// not part of it.
class Fields {
 public:
  explicit Fields(std::string_view line, Separator separator = Separator::blanks)
      : line_(line),
        mark_(separator == Separator::comma       ? ','
              : separator == Separator::semicolon ? ';'
                                                  : '\0') {}

  /// The next field; false when none is left.
  bool next(std::string_view& field) {
    if (mark_ != '\0') return next_before_mark(field);
    while (position_ < line_.size() && is_blank(line_[position_])) ++position_;
    if (position_ >= line_.size()) return false;
    const std::size_t begin = position_;
    while (position_ < line_.size() && !is_blank(line_[position_])) ++position_;
    field = line_.substr(begin, position_ - begin);
    return true;
  }

  /// Counts the fields left (consumes them).
  std::size_t count_rest() {
    std::size_t n = 0;
    for (std::string_view ignored; next(ignored);) ++n;
    return n;
  }

 private:
  bool next_before_mark(std::string_view& field) {
    if (position_ > line_.size()) return false;
    const std::size_t end = std::min(line_.find(mark_, position_), line_.size());
    field = trim(line_.substr(position_, end - position_));
    position_ = end + 1;
    return true;
  }

  std::string_view line_;
  char mark_;  ///< ',' or ';'; '\0' for blanks
  std::size_t position_ = 0;
};

/// Walks the rest of a keyword-led text (OBJ statements, Hoppe's .pts
/// records): for each line that holds a field once its comment is removed,
/// calls `statement(line_number, keyword, fields)` with its first field and
/// the fields after it. Blank and comment-only lines are skipped.
template <typename Statement>
void for_each_statement(LineScanner& lines, Statement&& statement) {
  std::string_view line;
  while (lines.next(line)) {
    Fields fields(without_comment(line));
    std::string_view keyword;
    if (fields.next(keyword)) statement(lines.line_number(), keyword, fields);
  }
}

/// Whitespace-separated tokens of a text across line ends, remembering on
/// which line each token stands.
class TokenScanner {
 public:
  /// Starts at byte `start`, which is the beginning of line `line`; `file`
  /// names the file in error messages.
  TokenScanner(std::string_view file, std::string_view text, std::size_t start, std::size_t line)
      : file_(file), text_(text), position_(start), line_start_(start), line_number_(line), token_line_(line) {
    if (start > 0 && start <= text.size() && text[start - 1] == '\n' && line > 1) token_line_ = line - 1;
  }

  /// The next token; false at the end of the text.
  bool next(std::string_view& token) {
    const std::size_t size = text_.size();
    while (position_ < size) {
      const char c = text_[position_];
      if (c == '\n') {
        ++line_number_;
        line_start_ = position_ + 1;
      } else if (!is_blank(c)) {
        break;
      } else {
        check_line_length();
      }
      ++position_;
    }
    if (position_ >= size) {
      line_number_ = token_line_;  // report the end of the data, not the blank lines after it
      return false;
    }
    const std::size_t begin = position_;
    while (position_ < size && text_[position_] != '\n' && !is_blank(text_[position_])) {
      if (text_[position_] == '\0') fail_nul_byte(file_, line_number_, position_ - line_start_ + 1);
      ++position_;
      check_line_length();
    }
    token = text_.substr(begin, position_ - begin);
    token_line_ = line_number_;
    return true;
  }

  /// The line of the token last returned; at the end of the text, the line
  /// of the last token (or of the text before `start` when there was none).
  [[nodiscard]] std::size_t line_number() const { return line_number_; }
  [[nodiscard]] std::size_t bytes_left() const { return text_.size() - position_; }
  /// Byte offset just after the token last returned.
  [[nodiscard]] std::size_t position() const { return position_; }

 private:
  void check_line_length() const {
    if (position_ - line_start_ > max_line_length) fail_long_line(file_, line_number_);
  }
  std::string_view file_;
  std::string_view text_;
  std::size_t position_;
  std::size_t line_start_;  ///< first byte of the current line
  std::size_t line_number_;
  std::size_t token_line_;
};

}  // namespace recon::io::detail
