// What each column of delimited text holds (see text_columns.h): the
// layout of the file, the plan from a header, --columns or the column count,
// and the decision, at the end of the file, about the columns whose meaning
// the values settle.

#include "text_columns.h"

#include "recon/core/errors.h"

#include <array>
#include <cstdio>
#include <iterator>
#include <utility>

namespace recon::io::detail {

// ---------------------------------------------------------------------------
// The layout: byte-order mark, line ends, header, separator

namespace {

bool separates_names(char c) { return is_blank(c) || c == ',' || c == ';'; }

/// The words of a header line, split at blanks, commas and semicolons, with
/// a leading "//" and double quotes around a word removed.
std::vector<std::string> header_words(std::string_view data) {
  std::string_view rest = trim(data);
  if (rest.starts_with("//")) rest.remove_prefix(2);
  std::vector<std::string> words;
  std::size_t i = 0;
  while (i < rest.size()) {
    while (i < rest.size() && separates_names(rest[i])) ++i;
    const std::size_t begin = i;
    while (i < rest.size() && !separates_names(rest[i])) ++i;
    std::string_view word = rest.substr(begin, i - begin);
    if (word.size() >= 2 && word.front() == '"' && word.back() == '"') word = word.substr(1, word.size() - 2);
    if (!word.empty()) words.emplace_back(word);
  }
  return words;
}

Separator separator_of(std::string_view data) {
  if (data.find(';') != std::string_view::npos) return Separator::semicolon;
  if (data.find(',') != std::string_view::npos) return Separator::comma;
  return Separator::blanks;
}

std::string_view plural_name(Separator separator) {
  switch (separator) {
    case Separator::blanks:
      return "blanks";
    case Separator::comma:
      return "commas";
    case Separator::semicolon:
      return "semicolons";
  }
  return "";
}

/// A character in `field` that separates columns in other files but not in
/// this one ('\0' when none): a comma or semicolon between blanks, a
/// semicolon or blank between commas, a blank between semicolons (where a
/// comma is a decimal mark).
char foreign_separator(std::string_view field, Separator separator) {
  for (const char c : field) {
    const bool foreign = separator == Separator::blanks  ? c == ',' || c == ';'
                         : separator == Separator::comma ? c == ';' || is_blank(c)
                                                         : is_blank(c);
    if (foreign) return c;
  }
  return '\0';
}

/// In a file without a header the first line of numbers sets the column
/// count: its fields must be whole (no empty field, one separator).
void check_first_fields(std::string_view file, std::size_t line, std::string_view data, const TextLayout& layout) {
  Fields fields(data, layout.separator);
  for (std::string_view field; fields.next(field);)
    if (field.empty() || foreign_separator(field, layout.separator) != '\0')
      fail_text_field(file, line, field, "", NumberStatus::not_a_number, layout);
}

}  // namespace

bool is_header_line(std::string_view data) {
  if (trim(data).starts_with("//")) return true;
  double ignored = 0.0;
  for (const std::string& word : header_words(data))
    if (parse_double(word, ignored) == NumberStatus::ok) return false;
  return true;
}

TextLayout find_text_layout(std::string_view file, std::string_view content) {
  TextLayout layout;
  layout.start = byte_order_mark_length(content);
  layout.line_ends = detect_line_ends(content, layout.start);
  LineScanner lines = layout_lines(file, content, layout);
  bool first = true;
  for (std::string_view line; lines.next(line);) {
    const std::string_view data = without_comment(line);
    if (is_blank_line(data)) continue;
    if (std::exchange(first, false) && is_header_line(data)) {
      layout.header_line = lines.line_number();
      layout.header = header_words(data);
      continue;
    }
    layout.first_line = lines.line_number();
    layout.separator = separator_of(data);
    layout.columns = Fields(data, layout.separator).count_rest();
    layout.first_data = data;
    break;
  }
  return layout;
}

// ---------------------------------------------------------------------------
// Numbers

void fail_text_field(std::string_view file, std::size_t line, std::string_view field, std::string_view what,
                     NumberStatus status, const TextLayout& layout) {
  const std::string_view mark = layout.separator == Separator::semicolon ? "semicolon" : "comma";
  if (field.empty())
    fail_at_line(file, line,
                 "an empty field (two " + std::string(mark) + "s in a row, or a " + std::string(mark) +
                     " at the start or end of the line) where a number belongs");
  if (const char c = foreign_separator(field, layout.separator); c != '\0') {
    const std::string found = c == ',' ? "a comma" : c == ';' ? "a semicolon" : "a blank";
    const std::string where = line == layout.first_line
                                  ? "this line"
                                  : "line " + std::to_string(layout.first_line) + ", the first of numbers,";
    fail_at_line(file, line,
                 "mixed separators: " + excerpt(field) + " holds " + found + ", but " + where + " separates its " +
                     "columns by " + std::string(plural_name(layout.separator)) +
                     "; one separator (blanks, commas or semicolons) must serve the whole file");
  }
  fail_at_line(file, line, describe_bad_number(status, field, what));
}

double parse_number_with_decimal_comma(std::string_view file, std::size_t line, std::string_view field,
                                       std::string_view what, const TextLayout& layout) {
  double value = 0.0;
  NumberStatus status = parse_double(field, value);
  // Between semicolons a comma is the decimal mark ("1,5;2;3"): read it as
  // a point. A number of more than 64 characters is no coordinate anyway.
  constexpr std::size_t longest = 64;
  if (status != NumberStatus::ok && layout.separator == Separator::semicolon && field.size() <= longest &&
      field.find(',') != std::string_view::npos) {
    char buffer[longest];
    std::replace_copy(field.begin(), field.end(), buffer, ',', '.');
    status = parse_double(std::string_view(buffer, field.size()), value);
    if (status == NumberStatus::ok) return value;
  }
  fail_text_field(file, line, field, what, status, layout);
}

// ---------------------------------------------------------------------------
// Column names

namespace {

struct KnownName {
  std::string_view name;
  ColumnRole role;
};
constexpr KnownName known_names[] = {
    {"x", ColumnRole::x},         {"y", ColumnRole::y},     {"z", ColumnRole::z},         {"nx", ColumnRole::nx},
    {"ny", ColumnRole::ny},       {"nz", ColumnRole::nz},   {"normal_x", ColumnRole::nx}, {"normal_y", ColumnRole::ny},
    {"normal_z", ColumnRole::nz}, {"r", ColumnRole::r},     {"g", ColumnRole::g},         {"b", ColumnRole::b},
    {"red", ColumnRole::r},       {"green", ColumnRole::g}, {"blue", ColumnRole::b},      {"_", ColumnRole::ignored},
};

/// The role `name` stands for; false when recon does not know the name.
bool known_role(std::string_view name, ColumnRole& role) {
  const std::string lower = lower_case(name);
  for (const KnownName& known : known_names) {
    if (known.name == lower) {
      role = known.role;
      return true;
    }
  }
  return false;
}

/// The short name of each ColumnRole, in the enumeration's order.
constexpr std::string_view role_text[] = {"_", "x", "y", "z", "nx", "ny", "nz", "r", "g", "b"};
using RoleColumns = std::array<std::size_t, std::size(role_text)>;

std::string_view text_of(ColumnRole role) { return role_text[static_cast<std::size_t>(role)]; }

ColumnRole role_plus(ColumnRole first, std::size_t k) {
  return static_cast<ColumnRole>(static_cast<std::size_t>(first) + k);
}

/// Which of a triple (x y z, nx ny nz, r g b) `role` is: 0, 1 or 2.
std::uint8_t place_in_triple(ColumnRole role, ColumnRole first) {
  return static_cast<std::uint8_t>(static_cast<int>(role) - static_cast<int>(first));
}

/// The columns holding each role (npos when none); throws when a role other
/// than `ignored` is named twice.
RoleColumns columns_of_roles(const std::vector<ColumnRole>& roles, const auto& fail) {
  RoleColumns at;
  at.fill(std::string::npos);
  for (std::size_t c = 0; c < roles.size(); ++c) {
    const auto r = static_cast<std::size_t>(roles[c]);
    if (roles[c] == ColumnRole::ignored) continue;
    if (at[r] != std::string::npos)
      fail("names " + std::string(text_of(roles[c])) + " twice (columns " + std::to_string(at[r] + 1) + " and " +
           std::to_string(c + 1) + ")");
    at[r] = c;
  }
  return at;
}

/// A triple (nx ny nz, or r g b) of which only some are named.
bool partly_named(const RoleColumns& at, ColumnRole first) {
  std::size_t named = 0;
  for (std::size_t k = 0; k < 3; ++k)
    if (at[static_cast<std::size_t>(role_plus(first, k))] != std::string::npos) ++named;
  return named == 1 || named == 2;
}

/// Drops a partly named triple to `ignored`, returning the remark for the note.
std::string drop_partial_triple(std::vector<ColumnRole>& roles, ColumnRole first, std::string_view what) {
  std::string dropped;
  for (ColumnRole& role : roles) {
    if (role >= first && role <= role_plus(first, 2)) {
      dropped += std::string(dropped.empty() ? "" : " ") + std::string(text_of(role));
      role = ColumnRole::ignored;
    }
  }
  return dropped + " ignored: " + std::string(what) + " need all three";
}

/// The plan for columns whose roles are named (by a header or --columns).
ColumnPlan named_plan(std::vector<ColumnRole> roles, const std::vector<std::string>& names, ColumnPlan::Source source) {
  ColumnPlan plan;
  plan.source = source;
  plan.fields.resize(roles.size());
  for (std::size_t c = 0; c < roles.size(); ++c) {
    const ColumnRole role = roles[c];
    FieldTarget& target = plan.fields[c];
    if (role >= ColumnRole::x && role <= ColumnRole::z) {
      target = {FieldTarget::Kind::position, place_in_triple(role, ColumnRole::x)};
    } else if (role >= ColumnRole::nx && role <= ColumnRole::nz) {
      target = {FieldTarget::Kind::normal, place_in_triple(role, ColumnRole::nx)};
    } else if (role >= ColumnRole::r) {
      target = {FieldTarget::Kind::held, place_in_triple(role, ColumnRole::r)};  // the held slots are r, g, b
    }
    plan.names.emplace_back(role == ColumnRole::ignored ? names[c] : std::string(text_of(role)));
  }
  // The columns of the held slots r, g, b, whatever the column order.
  for (const ColumnRole colour : {ColumnRole::r, ColumnRole::g, ColumnRole::b})
    for (std::size_t c = 0; c < roles.size(); ++c)
      if (roles[c] == colour) plan.held_columns.push_back(c);
  plan.roles = std::move(roles);
  return plan;
}

ColumnPlan plan_from_option(const std::vector<std::string>& columns) {
  auto fail = [](const std::string& what) { throw InvalidInputError("--columns " + what); };
  std::vector<ColumnRole> roles;
  for (const std::string& name : columns) {
    ColumnRole role = ColumnRole::ignored;
    if (!known_role(name, role))
      fail("names an unknown column '" + name +
           "' (known names: x, y, z, nx, ny, nz, r, g, b, and _ for a column to skip)");
    roles.push_back(role);
  }
  const auto at = columns_of_roles(roles, fail);
  for (const ColumnRole axis : {ColumnRole::x, ColumnRole::y, ColumnRole::z})
    if (at[static_cast<std::size_t>(axis)] == std::string::npos) fail("must name x, y and z");
  if (partly_named(at, ColumnRole::nx)) fail("names only some of nx, ny, nz: normals need all three");
  if (partly_named(at, ColumnRole::r)) fail("names only some of r, g, b: colours need all three");
  std::vector<std::string> names;
  for (std::size_t c = 0; c < columns.size(); ++c) names.push_back("column " + std::to_string(c + 1));
  return named_plan(std::move(roles), names, ColumnPlan::Source::option);
}

ColumnPlan plan_from_header(std::string_view file, const TextLayout& layout) {
  auto fail = [&](const std::string& what) { fail_at_line(file, layout.header_line, "the header line " + what); };
  std::vector<ColumnRole> roles;
  std::string ignored;
  for (const std::string& name : layout.header) {
    const ColumnRole role = role_named(name);
    if (role == ColumnRole::ignored) ignored += (ignored.empty() ? "" : ", ") + name;
    roles.push_back(role);
  }
  const auto at = columns_of_roles(roles, fail);
  for (const ColumnRole axis : {ColumnRole::x, ColumnRole::y, ColumnRole::z}) {
    if (at[static_cast<std::size_t>(axis)] == std::string::npos) {
      std::string words;
      for (const std::string& name : layout.header) words += (words.empty() ? "'" : ", '") + name + "'";
      fail("names no x, y and z column (it holds " + (words.empty() ? std::string("no names") : words) +
           "): name them in the header (x y z, nx ny nz, r g b, others are skipped) or give the columns "
           "with --columns, e.g. --columns x,y,z");
    }
  }
  std::vector<std::string> remarks;
  if (!ignored.empty()) remarks.push_back("ignored: " + ignored);
  if (partly_named(at, ColumnRole::nx)) remarks.push_back(drop_partial_triple(roles, ColumnRole::nx, "normals"));
  if (partly_named(at, ColumnRole::r)) remarks.push_back(drop_partial_triple(roles, ColumnRole::r, "colours"));
  ColumnPlan plan = named_plan(std::move(roles), layout.header, ColumnPlan::Source::header);
  plan.header_line = layout.header_line;
  plan.remarks = std::move(remarks);
  return plan;
}

/// Without a header or --columns: x y z, then what the count allows.
ColumnPlan guessed_plan(std::string_view file, const TextLayout& layout) {
  check_first_fields(file, layout.first_line, layout.first_data, layout);
  const std::size_t n = layout.columns;
  if (n != 3 && n != 4 && n != 6 && n != 7 && n != 9) {
    std::string example = "x,y,z";
    for (std::size_t c = 3; c < n; ++c) example += ",_";
    fail_at_line(file, layout.first_line,
                 "expected 3 numbers (x y z), 4 (and a value recon ignores), 6 (and normals or colours), 7 (a "
                 "value and normals or colours) or 9 (normals and colours) on a line, found " +
                     std::to_string(n) +
                     (n == 2  ? " (two columns are 2D points: recon reconstruct makes curves of them)"
                      : n < 3 ? ""
                              : "; name the columns in a header line or with --columns, e.g. --columns " + example));
  }
  ColumnPlan plan;
  for (std::size_t c = 0; c < n; ++c) {
    if (c < 3) {
      plan.roles.push_back(role_plus(ColumnRole::x, c));
      plan.names.emplace_back(text_of(plan.roles.back()));
      plan.fields.push_back({FieldTarget::Kind::position, static_cast<std::uint8_t>(c)});
      continue;
    }
    plan.roles.push_back(ColumnRole::ignored);
    plan.names.push_back("column " + std::to_string(c + 1));
    if (n == 4) {
      plan.fields.push_back({FieldTarget::Kind::skip, 0});
    } else {
      plan.fields.push_back({FieldTarget::Kind::held, static_cast<std::uint8_t>(c - 3)});
      plan.held_columns.push_back(c);
    }
  }
  return plan;
}

}  // namespace

ColumnRole role_named(std::string_view name) {
  ColumnRole role = ColumnRole::ignored;
  return known_role(name, role) ? role : ColumnRole::ignored;
}

ColumnPlan plan_columns(std::string_view file, const TextLayout& layout, const std::vector<std::string>& columns) {
  if (!columns.empty()) {
    ColumnPlan plan = plan_from_option(columns);
    if (layout.header_line != 0)
      plan.remarks.push_back("the header on line " + std::to_string(layout.header_line) + " is not used");
    return plan;
  }
  if (layout.header_line != 0) return plan_from_header(file, layout);
  return guessed_plan(file, layout);
}

// ---------------------------------------------------------------------------
// Deciding the held columns

namespace {

/// Colours, or why the values cannot be colours.
struct ColourVerdict {
  double scale = 0.0;    ///< 0: not colours; 1: integers 0-255; 255: fractions 0-1
  std::string what;      ///< "integers 0-255", ...; or the problem, "300 for b is ..."
  std::size_t line = 0;  ///< where they were ruled out
};

/// The earliest of one kind of evidence over three held columns, with the slot.
std::pair<ColumnEvidence::Found, std::size_t> earliest(const std::vector<ColumnEvidence>& evidence, std::size_t slot,
                                                       ColumnEvidence::Found ColumnEvidence::*kind) {
  std::pair<ColumnEvidence::Found, std::size_t> best{{}, slot};
  for (std::size_t s = slot; s < slot + 3; ++s) {
    const ColumnEvidence::Found& found = evidence[s].*kind;
    if (found.line != 0 && (best.first.line == 0 || found.line < best.first.line)) best = {found, s};
  }
  return best;
}

/// A number for a message: at most 4 significant digits.
std::string short_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

ColourVerdict colour_verdict(const ColumnPlan& plan, const std::vector<ColumnEvidence>& evidence, std::size_t slot) {
  auto value_of = [&](const std::pair<ColumnEvidence::Found, std::size_t>& found) {
    return short_number(found.first.value) + " for " + plan.names[plan.held_columns[found.second]];
  };
  const auto not_colour = earliest(evidence, slot, &ColumnEvidence::not_colour);
  if (not_colour.first.line != 0)
    return {0.0, value_of(not_colour) + " is neither an integer 0 to 255 nor a fraction 0 to 1", not_colour.first.line};
  const auto fraction = earliest(evidence, slot, &ColumnEvidence::fraction);
  const auto above_one = earliest(evidence, slot, &ColumnEvidence::above_one);
  if (fraction.first.line != 0 && above_one.first.line != 0) {
    if (fraction.first.line < above_one.first.line)
      return {0.0,
              value_of(above_one) + " is above 1, but line " + std::to_string(fraction.first.line) +
                  " has a fraction (" + value_of(fraction) + ")",
              above_one.first.line};
    return {0.0,
            value_of(fraction) + " is a fraction, but line " + std::to_string(above_one.first.line) +
                " has an integer above 1 (" + value_of(above_one) + ")",
            fraction.first.line};
  }
  if (above_one.first.line != 0) return {1.0, "integers 0-255", 0};
  if (fraction.first.line != 0) return {255.0, "fractions 0-1, scaled to 0-255", 0};
  return {255.0, "only 0s and 1s, read as fractions 0-1 (1 is 255)", 0};
}

std::string span_text(const ColumnPlan& plan, std::size_t slot) {
  const std::size_t first = plan.held_columns[slot] + 1;
  return "columns " + std::to_string(first) + " to " + std::to_string(first + 2);
}

/// What a triple of a guessed plan holds: normals when it is a unit vector
/// on every line (even if its values would fit colours too), else colours
/// when they fit, else neither.
struct TripleFit {
  bool normals = false;
  bool colours = false;  ///< the values fit colours (also when normals is true)
  ColourVerdict colour;
  std::string why_not_normals;

  [[nodiscard]] bool none() const { return !normals && !colours; }
};

TripleFit fit_triple(const ColumnPlan& plan, const std::vector<ColumnEvidence>& columns,
                     const std::vector<TripleEvidence>& triples, std::size_t slot) {
  TripleFit fit;
  fit.colour = colour_verdict(plan, columns, slot);
  fit.colours = fit.colour.scale > 0.0;
  fit.normals = triples[slot].not_unit_line == 0;
  if (!fit.normals)
    fit.why_not_normals = "line " + std::to_string(triples[slot].not_unit_line) + " has a vector of length " +
                          short_number(triples[slot].not_unit_length);
  return fit;
}

/// "columns 4 to 6 are normals (...)" / "... neither normals (...) nor colours (...)".
std::string describe_fit(const ColumnPlan& plan, std::size_t slot, const TripleFit& fit) {
  const std::string span = span_text(plan, slot);
  if (fit.normals) return span + " could be normals (unit vectors on every line)";
  if (fit.colours) return span + " could be colours (" + fit.colour.what + ")";
  return span + " are neither normals (" + fit.why_not_normals + ") nor colours (line " +
         std::to_string(fit.colour.line) + ": " + fit.colour.what + ")";
}

/// The reason given in the note for a triple read as normals or colours.
std::string reason(const TripleFit& fit) {
  if (fit.normals && fit.colours)
    return "unit vectors on every line: normals (colours would fit too: --columns reads them as r,g,b)";
  if (fit.normals) return "unit vectors on every line: normals";
  if (fit.colour.scale == 1.0) return "integers 0-255: colours";
  return "not unit vectors but " + fit.colour.what + ": colours";
}

[[noreturn]] void refuse_guess(std::string_view file, const std::string& why, std::size_t columns) {
  const std::string example = columns == 6   ? "--columns x,y,z,nx,ny,nz or --columns x,y,z,r,g,b"
                              : columns == 7 ? "--columns x,y,z,_,r,g,b or --columns x,y,z,r,g,b,_"
                                             : "--columns x,y,z,nx,ny,nz,r,g,b";
  fail_in_file(file, "the columns after x y z leave doubt: " + why + "; name the columns in a header line or with " +
                         example + " (_ skips a column)");
}

void use_triple(ColumnPlan& plan, HeldUse& use, std::size_t slot, const TripleFit& fit) {
  const ColumnRole first = fit.normals ? ColumnRole::nx : ColumnRole::r;
  for (std::size_t k = 0; k < 3; ++k) plan.roles[plan.held_columns[slot + k]] = role_plus(first, k);
  if (fit.normals) {
    use.normals = static_cast<int>(slot);
  } else {
    use.colours = static_cast<int>(slot);
    use.colour_scale = fit.colour.scale;
  }
}

/// Four, six, seven or nine columns without names (see text_columns.h):
/// the reason the note gives.
std::string decide_guessed(std::string_view file, ColumnPlan& plan, const std::vector<ColumnEvidence>& columns,
                           const std::vector<TripleEvidence>& triples, HeldUse& use) {
  const std::size_t n = plan.roles.size();
  if (n == 4) return "the 4th column, such as an intensity, is ignored";
  if (n == 6 || n == 9) {
    const TripleFit first = fit_triple(plan, columns, triples, 0);
    if (n == 6) {
      if (first.none()) refuse_guess(file, describe_fit(plan, 0, first), n);
      use_triple(plan, use, 0, first);
      return "the last three are " + reason(first);
    }
    const TripleFit second = fit_triple(plan, columns, triples, 3);
    if (first.none() || second.none() || first.normals == second.normals)
      refuse_guess(file, describe_fit(plan, 0, first) + ", and " + describe_fit(plan, 3, second), n);
    use_triple(plan, use, 0, first);
    use_triple(plan, use, 3, second);
    return "columns 4 to 6 are " + reason(first) + "; 7 to 9 are " + reason(second);
  }
  // Seven: a value before or after the triple, whichever placement alone fits.
  const TripleFit before = fit_triple(plan, columns, triples, 1);
  const TripleFit after = fit_triple(plan, columns, triples, 0);
  const bool value_first = !before.none() && after.none();
  const bool value_last = !after.none() && before.none();
  if (!value_first && !value_last)
    refuse_guess(file, describe_fit(plan, 0, after) + ", and " + describe_fit(plan, 1, before), n);
  const std::size_t slot = value_first ? 1 : 0;
  use_triple(plan, use, slot, value_first ? before : after);
  return span_text(plan, slot) + " are " + reason(value_first ? before : after) + "; column " +
         std::to_string(value_first ? 4 : 7) + " is ignored";
}

std::string roles_text(const ColumnPlan& plan) {
  std::string text;
  for (const ColumnRole role : plan.roles) text += (text.empty() ? "" : " ") + std::string(text_of(role));
  return text;
}

}  // namespace

HeldUse decide_columns(std::string_view file, ColumnPlan& plan, const std::vector<ColumnEvidence>& columns,
                       const std::vector<TripleEvidence>& triples, ReadNotes& notes) {
  HeldUse use;
  if (plan.guessed()) {
    if (plan.roles.size() == 3) return use;
    const std::string why = decide_guessed(file, plan, columns, triples, use);
    notes.lines.push_back("columns: " + roles_text(plan) + " (no header; " + why + ")");
    return use;
  }
  std::string said = plan.source == ColumnPlan::Source::option
                         ? "from --columns"
                         : "from the header on line " + std::to_string(plan.header_line);
  if (plan.held() == 3) {
    const ColourVerdict colour = colour_verdict(plan, columns, 0);
    if (colour.scale == 0.0)
      fail_at_line(file, colour.line,
                   "colour value out of range: " + colour.what +
                       " (colours are integers 0 to 255 or fractions 0 to 1, one or the other in the whole file)");
    use.colours = 0;
    use.colour_scale = colour.scale;
    said += "; colours: " + colour.what;
  }
  for (const std::string& remark : plan.remarks) said += "; " + remark;
  notes.lines.push_back("columns: " + roles_text(plan) + " (" + said + ")");
  return use;
}

}  // namespace recon::io::detail
