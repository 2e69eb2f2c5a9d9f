// tiltfield: small I/O helpers every writer and reader shares.
#pragma once
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

namespace tf {

// Writes through `fill` to "<file>.tmp-<pid>" in the same folder, then renames onto `file`, so a failed
// run never leaves a half-written file under the requested name. Throws std::runtime_error when the
// folder cannot be written or `fill` throws (the temporary is removed).
void write_file_atomic(const std::filesystem::path& file, const std::function<void(std::ostream&)>& fill);

// The same for writers that want a path (e.g. OpenMesh): `write` receives the temporary path.
void write_path_atomic(const std::filesystem::path& file,
                       const std::function<void(const std::filesystem::path& tmp)>& write);

// The whole file as bytes. Throws InputError(file, 0, "", "cannot read the <what>") when it cannot be read.
std::string read_text_file(const std::filesystem::path& file, const std::string& what = "file");

// `text` without the UTF-8 byte-order mark (EF BB BF) that some Windows editors and spreadsheets write
// first; the CSV, profile, CLDATA and grinding-program readers skip it (a CSV's first column was read as
// "\xEF\xBB\xBFx", "missing column x"). G-code keeps it: rs274 refuses it, and so does the reader.
std::string_view without_utf8_bom(std::string_view text);
bool starts_with_utf8_bom(std::string_view text);

// Formats a number in fixed notation with at most `decimals` decimals, trailing zeros and a trailing
// point removed, "-0" written as "0". Never scientific notation.
std::string fixed(double v, int decimals);

// A CSV table with a header row. Cells are trimmed; blank lines and lines starting with '#' skipped.
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lines;  // 1-based source line of each row
  int column(std::string_view name) const;  // -1 when absent
};
// Throws InputError(file, line, "", ...) on a row whose cell count differs from the header's, or an
// unreadable file.
CsvTable read_csv(const std::filesystem::path& file);

// Parses a finite double; throws InputError(file, line, field, ...) otherwise.
double parse_number(std::string_view text, const std::string& file, int line, const std::string& field);
// parse_number for a coordinate, mm: also throws beyond kMaxCoordinate (1e200 hung the planner; 1e100
// came out as 100-digit G-code words).
inline constexpr double kMaxCoordinate = 1e6;
double parse_coordinate(std::string_view text, const std::string& file, int line, const std::string& field);

}  // namespace tf
