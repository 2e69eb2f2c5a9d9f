#include "tiltfield/core/io.hpp"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <vector>
#include <sstream>

#include "tiltfield/core/error.hpp"

namespace tf {
namespace fs = std::filesystem;

namespace {
fs::path temporary_for(const fs::path& file) {
  fs::path tmp = file;
  tmp += ".tmp-" + std::to_string(::getpid());
  return tmp;
}

std::string trim(std::string_view s) {
  size_t a = 0, b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\t' || s[a] == '\r' || s[a] == '\n')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t' || s[b - 1] == '\r' || s[b - 1] == '\n')) --b;
  return std::string(s.substr(a, b - a));
}
}  // namespace

namespace {
// The file a write to `file` replaces: the one a link names (the link stays; renaming over the link had
// replaced it with a regular file, its target unchanged), else `file` itself.
fs::path replaced_by_write(const fs::path& file) {
  std::error_code ec;
  fs::path at = file;
  for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(at, ec)); ++hops) {
    const fs::path to = fs::read_symlink(at, ec);  // a link to a file not yet made is followed too
    if (ec) return file;
    at = to.is_absolute() ? to : at.parent_path() / to;
  }
  return at;
}

// An existing file that is neither regular nor a folder: a device (/dev/null) or a fifo. It is written in
// place: renaming over it had replaced the device with a regular file (black-box testing, as root).
bool is_special_file(const fs::path& file) {
  std::error_code ec;
  const fs::file_status s = fs::status(file, ec);
  return !ec && fs::exists(s) && !fs::is_regular_file(s) && !fs::is_directory(s);
}

// Fills `out` and makes sure every byte reached the file: a full disk or a file-size limit had left a
// cut-off file under the output's name with exit 0.
void fill_checked(const fs::path& shown, const fs::path& path, bool temporary,
                  const std::function<void(std::ostream&)>& fill) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error(shown.string() + ": cannot write (folder missing or not writable)");
  errno = 0;  // the reason of a write that fails while filling, or at the flush
  fill(out);
  out.flush();
  out.close();
  if (out.fail())
    throw std::runtime_error(shown.string() + ": write failed" + (errno ? std::string(" (") + std::strerror(errno) + ")" : "") +
                             (temporary ? "; an earlier file of that name is left as it was" : ""));
}
}  // namespace

void write_path_atomic(const fs::path& file, const std::function<void(const fs::path&)>& write) {
  const fs::path target = replaced_by_write(file);
  const fs::path tmp = temporary_for(target);
  try {
    write(tmp);
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec)
      throw std::runtime_error(file.string() + ": cannot replace it (" + ec.message() +
                               "); an earlier file of that name is left as it was");
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

void write_file_atomic(const fs::path& file, const std::function<void(std::ostream&)>& fill) {
  // Asked first, following links as the kernel does: /dev/stdout's link names "pipe:[N]", no path (review).
  if (is_special_file(file)) return fill_checked(file, file, false, fill);
  const fs::path target = replaced_by_write(file);
  write_path_atomic(target, [&](const fs::path& tmp) { fill_checked(file, tmp, true, fill); });
}

std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) throw std::runtime_error("fixed(): non-finite number");
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s(buf);
  if (s.find('.') != std::string::npos) {
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

std::string read_text_file(const fs::path& file, const std::string& what) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) throw InputError(file.string(), 0, "", "is a directory, not a " + what);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), 0, "", "cannot read the " + what);
  // A device or a pipe may never end (/dev/zero): read in chunks up to a bound above any real program (a
  // 3-axis finish of millions of lines is a few hundred MB). A regular file is read whole.
  const size_t max_bytes = fs::is_regular_file(file, ec) ? std::numeric_limits<size_t>::max() : size_t(1) << 30;
  std::string text;
  std::vector<char> chunk(size_t(1) << 20);
  while (in) {
    in.read(chunk.data(), std::streamsize(chunk.size()));
    const std::streamsize got = std::min<std::streamsize>(in.gcount(), std::streamsize(chunk.size()));
    if (got > 0) text.append(chunk.data(), size_t(got));
    if (text.size() > max_bytes)
      throw InputError(file.string(), 0, "", "the " + what + " is not a file and gives more than 1 GiB (or never ends)");
  }
  if (in.bad()) throw InputError(file.string(), 0, "", "cannot read the " + what);
  return text;
}

int CsvTable::column(std::string_view name) const {
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return static_cast<int>(i);
  return -1;
}

bool starts_with_utf8_bom(std::string_view text) { return text.substr(0, 3) == "\xEF\xBB\xBF"; }
std::string_view without_utf8_bom(std::string_view text) { return starts_with_utf8_bom(text) ? text.substr(3) : text; }

CsvTable read_csv(const fs::path& file) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) throw InputError(file.string(), 0, "", "is a directory, not a CSV file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), 0, "", "cannot open file");
  CsvTable t;
  std::string line;
  int n = 0;
  auto split = [](const std::string& l) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream ss(l);
    while (std::getline(ss, cell, ',')) cells.push_back(trim(cell));
    if (!l.empty() && l.back() == ',') cells.emplace_back();
    return cells;
  };
  while (std::getline(in, line)) {
    ++n;
    const std::string tl = trim(n == 1 ? without_utf8_bom(line) : std::string_view(line));
    if (tl.empty() || tl[0] == '#') continue;
    if (tl.find('\0') != std::string::npos) throw InputError(file.string(), n, "", "binary data in a CSV file");
    auto cells = split(tl);
    if (t.header.empty()) {
      // A file without its header row: its first row of numbers had been read as column names, and the
      // message spoke of a column appearing twice (black-box testing).
      const bool numbers = std::all_of(cells.begin(), cells.end(), [](const std::string& c) {
        double v = 0.0;
        const auto [ptr, ec] = std::from_chars(c.data(), c.data() + c.size(), v);
        return !c.empty() && ec == std::errc() && ptr == c.data() + c.size();
      });
      if (numbers) throw InputError(file.string(), n, "", "no header row: the first row holds numbers, not column names");
      // A column named twice is ambiguous (which one holds the feed?): the readers took the first.
      for (size_t i = 0; i < cells.size(); ++i)
        if (!cells[i].empty() && std::find(cells.begin(), cells.begin() + long(i), cells[i]) != cells.begin() + long(i))
          throw InputError(file.string(), n, cells[i], "the column appears twice in the header");
      t.header = cells;
      continue;
    }
    if (cells.size() != t.header.size())
      throw InputError(file.string(), n, "",
                       "expected " + std::to_string(t.header.size()) + " cells as in the header, found " +
                           std::to_string(cells.size()));
    t.rows.push_back(std::move(cells));
    t.lines.push_back(n);
  }
  if (t.header.empty()) throw InputError(file.string(), 0, "", "empty file: no header row");
  return t;
}

double parse_number(std::string_view text, const std::string& file, int line, const std::string& field) {
  std::string s = trim(text);
  if (!s.empty() && s[0] == '+') s.erase(0, 1);
  double v = 0.0;
  const char* b = s.data();
  const char* e = s.data() + s.size();
  auto [ptr, ec] = std::from_chars(b, e, v);
  if (s.empty() || ec != std::errc() || ptr != e)
    throw InputError(file, line, field, "'" + std::string(text) + "' is not a number");
  if (!std::isfinite(v)) throw InputError(file, line, field, "'" + std::string(text) + "' is not finite");
  return v;
}

double parse_coordinate(std::string_view text, const std::string& file, int line, const std::string& field) {
  const double v = parse_number(text, file, line, field);
  if (std::abs(v) > kMaxCoordinate)
    throw InputError(file, line, field, "'" + std::string(text) + "' mm is beyond 1 km: a wrong unit or a damaged row?");
  return v;
}

}  // namespace tf
