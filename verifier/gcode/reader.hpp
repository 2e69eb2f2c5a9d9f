// tiltfield gcode (internal): the reader's state machine, one instance per program. It follows LinuxCNC's
// interpreter: a block's words take effect in RS274/NGC's order of execution, positions are kept in the
// program's coordinates (the current coordinate system, mm and degrees) and every motion is emitted at
// the machine position programmed + work offset + G92 offset + tool length offset along Z.
//
// Split by subject: reader.cpp (lines, words, modal codes, M codes), motion.cpp (straight moves, arcs,
// G53, polar coordinates, G33 and G33.1, the emitted blocks), offsets.cpp (coordinate systems, G92, G10,
// tool length offsets, G28/G30, and the end of the program), cycles.cpp (canned cycles).
#pragma once
#include <Eigen/Core>
#include <array>
#include <deque>
#include <functional>
#include <initializer_list>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "tiltfield/core/error.hpp"
#include "tiltfield/gcode/gcode.hpp"
#include "expressions.hpp"
#include "words.hpp"

namespace tf::gcode {

using Axes = std::array<double, 6>;  // X Y Z (mm) A B C (deg)

inline int axis_index(char c) { return static_cast<int>(std::string_view("XYZABC").find(c)); }

// G54 ... G59.3 (keys 540 ... 593) -> 0 ... 8; -1 for another key.
inline int work_offset_index(int key) {
  if (key >= 540 && key <= 590 && key % 10 == 0) return (key - 540) / 10;
  if (key >= 591 && key <= 593) return key - 585;
  return -1;
}

// Subroutine and subprogram calls nest at most this deep (rs274: "Too many subroutine levels" at level 10).
inline constexpr size_t kMaxCallDepth = 9;

// Per block and axis: whether the program has set its position.
enum class AxisState : unsigned char { Set, NotYet, SentHome };

// G-code motion modes as code keys (G1 -> 10); kNoMotion before any, 800 after G80 (no mode either).
constexpr int kNoMotion = -1;
// The canned cycles G73, G74, G81-G89 (whole numbers: a G84.2 is not one).
inline bool is_cycle(int motion) {
  return motion % 10 == 0 && (motion == 730 || motion == 740 || (motion >= 810 && motion <= 890));
}

struct State {
  Axes pos{};                  // program coordinates in the current coordinate system
  std::array<AxisState, 6> axes{AxisState::NotYet, AxisState::NotYet, AxisState::NotYet,
                               AxisState::NotYet, AxisState::NotYet, AxisState::NotYet};
  int motion = kNoMotion;
  int plane = 17;
  bool cutter_comp = false;  // G41/G42 (or .1) in force: its rules are kept
  // The code that turned it on with an offset (a D other than 0): a move under it is refused, as the
  // compensated path is not simulated. Empty with D0, which offsets nothing.
  std::string comp_offset;
  bool inch = false;
  bool incremental = false;
  bool arc_incremental = true;  // G91.1 default
  bool inverse_time = false;
  bool tcp = false;       // tool-centre-point control on
  bool tcp_g434 = false;  // switched on by G43.4 (which G49 cancels), not by an M code
  bool tcp_switched = false;  // TCP switched after motion, and no motion block since
  double feed = 0.0;
  double feed_word = 0.0;  // F as written (#<_feed>: LinuxCNC does not convert it when the units change)
  double spindle = 0.0;
  int spindle_dir = 0;    // 1 M3, -1 M4, 0 stopped
  int tool = 0, pending_tool = 0;
  bool empty_spindle = false;  // T0 M6 with a tool library
  int tool_line = 0;           // where the tool in the spindle was loaded
  double tlo = 0.0;            // tool length offset in force (G43), mm along Z
  int cs = 0;                  // coordinate system 0..8: G54 ... G59.3
  std::array<Axes, 9> offsets{};
  std::array<bool, 9> defined{};
  Axes g92{}, g92_saved{};
  // Canned cycles (LinuxCNC's cycle_il, cycle_r, cycle_cc, cycle_p, cycle_q); G99 is its default. The
  // initial level, R, the bottom and Q are kept in program units: after G20/G21 LinuxCNC reads the same
  // numbers in the new units (a G98 retract after G21 goes to the initial level's inches taken as mm).
  bool retract_r_plane = true;
  bool cycle_il_flag = false;
  double cycle_il = 0.0, cycle_r = 0.0, cycle_cc = 0.0, cycle_p = 0.0, cycle_q = 0.0;
  double dwell = 0.0;          // seconds before the next motion block
  bool ended = false;
  bool percent = false;        // a "%" line opened the program; the next one ends it
  bool started = false;        // a line that is not blank was read: a "%" now only ends an opened program
};

class Reader : private ParameterValues {
 public:
  Reader(const std::string& file, const MachineSpec& machine, const GcodeOptions& options);
  // Reads the program's lines (without their line ends), in the order its control flow takes them.
  void run(const std::vector<std::string_view>& lines);
  Program finish();

 private:
  // control.cpp: O-word subroutines and control flow
  struct OLine {
    OWord word;
    std::string code;
  };
  struct Sub {
    size_t begin, end;  // the lines (0-based) of its SUB and ENDSUB
  };
  struct Frame {
    size_t return_to;              // the line after the CALL (or M98)
    std::array<double, 31> saved;  // the caller's #1 ... #30 (an O-word call's)
    size_t loops;                  // the caller's open loops
    bool fanuc = false;            // a program called by M98, which M99 ends
    size_t start = 0;              // M98: the program's "O1000" line
    long passes_left = 0;          // M98: the runs after this one (L)
  };
  enum class LoopKind { While, Do, Repeat };
  struct Loop {
    std::string label;
    LoopKind kind;
    size_t head;     // While: its WHILE line; Do, Repeat: the first line of the body
    long remaining;  // Repeat: passes left
  };
  void scan_o_words(size_t begin, size_t end);
  void control(const OLine& o, size_t at, size_t& next);
  void call(const OLine& o, int number, size_t& next);
  void enter_call(const Frame& f, int number, const std::string& field);
  bool fanuc_line(const std::string& code, size_t at, size_t& next);
  void m98(const std::string& code, int number, size_t& next);
  void m99(const std::string& code, int number, size_t& next);
  void return_from(const OLine& o, int number, size_t& next);
  void loop_end(const OLine& o, int number, size_t& next);
  void break_or_continue(const OLine& o, size_t at, size_t& next);
  bool condition(const OLine& o, int number);
  size_t find_o_word(size_t from, const OWord& o, std::initializer_list<std::string_view> keywords) const;

  // subroutine_files.cpp: O<name> subroutines from the files <name>.ngc (GcodeOptions::subroutine_dirs),
  // appended to lines_ as they are first called, and where each line of lines_ comes from
  struct Source {
    size_t begin, end;  // its lines in lines_
    std::string file;
    int first_line;     // the file's line number of lines_[begin]
  };
  bool load_subroutine_file(const std::string& label, int number);
  std::pair<std::string, int> source_of(int number) const;  // the file and line of a line of lines_ (1-based)
  InputError in_source(const InputError& e) const;
  size_t source_end(size_t at) const;                         // the end of the lines of the file that holds `at`
  int block_line(int number) const;
  std::string line_name(int number) const;  // "line 12", or "sub.ngc:3" for a subroutine file's line

  std::optional<std::string> code_of(std::string_view raw, int number);
  void check_length(std::string_view raw, int number) const;
  void execute(const std::string& code, int number);

  // parameters.cpp: the values a line's parameters read, and its settings
  std::optional<double> numbered(int k) const override;
  std::optional<double> named(const std::string& name) const override;
  bool defined(const std::string& name) const override;
  std::optional<double> predefined(const std::string& name) const;
  double position(int axis, const std::string& parameter) const;  // program units
  void set_parameters(const std::vector<ParameterSetting>& settings, int line);

  // reader.cpp
  void warn(int line, const std::string& code, const std::string& what);
  void block(const std::vector<Word>& words, int line);
  void sort_words(const std::vector<Word>& words, int line, Values& val, std::vector<int>& gs, std::vector<int>& ms) const;
  void apply_m_codes(const std::vector<int>& ms, const Values& val, int line);
  // Tool-centre-point control on or off (g434: by G43.4, which G43 and G49 end).
  void set_tcp(bool on, bool g434);
  void apply_units_and_feed_mode(const std::vector<int>& gs, int line);
  void apply_modal_g_codes(const std::vector<int>& gs, const Values& val, int line);
  void apply_feed_speed_tool(const Values& val, int line);
  double unit() const { return st_.inch ? 25.4 : 1.0; }
  double length(char axis, double v) const { return axis_index(axis) < 3 ? v * unit() : v; }

  // motion.cpp
  void motion_block(int motion, bool g53, const Values& val, int line);
  Axes move_axes(const Values& val);
  void check_polar(const Values& val, const std::optional<int>& axis_code, bool g53, int line) const;
  void polar_target(const Values& val, int line);
  void polar_step(double& x, double& y, const Values& val, bool skip_zero, int line) const;
  void spindle_synchronized(int motion, const Axes& start, const Values& val, int line);
  void check_unused_words(const std::optional<int>& motion, const std::optional<int>& nonmodal, bool moves,
                          const std::vector<int>& gs, const std::vector<int>& ms, const Values& val, int line) const;
  void assume_position(int axis);
  void emit(Motion m, const Axes& target, int line, const Eigen::Vector3d* centre = nullptr);
  void arc(int motion, const Axes& start, const Axes& end, const Values& val, int line);
  Eigen::Vector3d arc_center(bool ccw, const Axes& start, const Axes& end, const Values& val, int line) const;
  void refuse_compensated(int line) const;
  bool r_form_is_straight(const Axes& start, const Axes& end, const Eigen::Vector3d& centre) const;
  void check_tool(int line) const;

  // offsets.cpp
  Axes offset() const;  // program -> machine: work offset + G92 + tool length along Z
  void set_offset_keeping_position(const std::function<void()>& change);
  void select_coordinate_system(int key, int line);
  void set_g92(int key, const Values& val, int line);
  void drop_blocks_sent_home(const std::vector<bool>& drop);
  void g10(const Values& val, int line);
  void tool_length_offset(int key, const Values& val, int line);
  double tool_length(int number, int line, const std::string& word) const;
  void reference_return(int key, const Values& val, int line);
  void fill_unknown_axes();
  void tool_tip_targets();
  bool convert_position_for_tcp(bool on);

  // splines.cpp
  void spline(int motion, const Values& val, int line);

  // cycles.cpp
  void canned_cycle(int motion, const Values& val, int line);
  void cycle_move(bool feed, const std::array<int, 3>& plane_axes, double a, double b, double c, int line);

  std::string file_;
  const MachineSpec& machine_;
  GcodeOptions options_;
  std::optional<int> tcp_on_, tcp_off_;
  State st_;
  Program program_;
  std::vector<std::array<AxisState, 6>> axes_;  // per block: which axes the program has set
  std::vector<double> block_tlo_;           // per block: the tool length offset in force
  bool uses_length_offsets_ = false;        // G43 / G43.4 anywhere
  bool tcp_converted_without_offsets_ = false;  // a TCP switch converted the position before any G43
  int reference_line_ = 0;                  // the last G28/G30
  std::set<std::string> warned_;
  std::vector<double> numbered_ = std::vector<double>(kMaxParameter + 1, 0.0);  // #1 ... #5000 (index = number)
  std::map<std::string, double> globals_;                    // #<_name>
  std::vector<std::map<std::string, double>> locals_{1};      // #<name>, per call level (the main program's first)
  double value_ = 0.0, value_returned_ = 0.0;                 // #<_value>, #<_value_returned>
  std::vector<std::string_view> lines_;                       // the program's lines, then the subroutine files'
  size_t main_lines_ = 0;                                     // the program's own
  std::deque<std::string> file_texts_;                        // the subroutine files read
  std::vector<Source> sources_;                               // their lines in lines_
  std::vector<std::optional<OLine>> o_lines_;                 // per line (0-based)
  std::map<std::string, Sub> subs_;                           // by label
  std::map<std::string, size_t> programs_;                    // Fanuc-style "O1000" lines, by number
  std::vector<Frame> calls_;
  std::vector<Loop> loops_;
  int line_ = 0;  // the line being read (for a parameter's errors)
  bool synchronized_ = false;  // emitting a G33/G33.1 move
  unsigned char from_reference_ = 0;  // axes sent to the reference since the last block (Block::from_reference)
  double time_share_ = 1.0;    // emitting one of the blocks one G93 F times together (Block::time_share)
  Eigen::Vector2d spline_mirror_ = Eigen::Vector2d::Zero();  // the last G5's -P, -Q as written (LinuxCNC's cycle_i, cycle_j)
};

}  // namespace tf::gcode
