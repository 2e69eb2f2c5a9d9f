// The G-code reader's entry points and its block dispatch: words sorted, then executed in RS274/NGC's
// order (feed mode, F S T, M codes, dwell, modal G codes, G10/G28/G30/G92, motion, stops).
#include "reader.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"

namespace tf {
namespace gcode {
namespace {

// The longest line rs274 reads (its count includes the "\r" of a "\r\n"): 253 characters are
// "Command too long".
constexpr size_t kMaxLineLength = 252;

// What a G code of the motion group or of the non-modal group 0 is, for the block dispatch.
bool is_motion_code(int g) {
  return g == 0 || g == 10 || g == 20 || g == 30 || g == 50 || g == 51 || g == 330 || g == 331 || g == 800 || is_cycle(g);
}
bool is_nonmodal_axis_code(int g) {  // group 0 codes that take the block's axis words
  return g == 100 || g == 280 || g == 300 || g == 520 || g == 920;
}

// Every G code the reader acts on or accepts without effect (G8 radius mode; G96, G97 spindle speed modes).
bool recognised(int g) {
  static const std::set<int> codes = {40,  80,  170, 180, 190, 200, 210, 281, 301, 400, 410, 411, 420, 421, 430,
                                      431, 432, 434, 490, 530, 610, 611, 640, 900, 901, 910, 911, 921, 922, 923,
                                      930, 940, 960, 970, 980, 990};
  return codes.count(g) || (g >= 540 && g <= 593 && work_offset_index(g) >= 0) || is_motion_code(g) ||
         is_nonmodal_axis_code(g);
}

// The M codes apply_m_codes acts on or accepts (RS274/NGC's own), whose words RS274/NGC fixes.
bool known_m_code(int m) {
  static const std::set<int> codes = {0,   10,  20,  30,  40,  50,  60,  70,  80,  90,  190, 300, 480, 490,
                                      500, 510, 520, 530, 600, 610, 620, 630, 640, 650, 660, 670, 680, 700,
                                      710, 720, 730, 980, 990, 1280, 1290};
  return codes.count(m) > 0;
}

}  // namespace

Reader::Reader(const std::string& file, const MachineSpec& machine, const GcodeOptions& options)
    : file_(file), machine_(machine), options_(options) {
  if (auto k = machine_m_code(machine.tcp_on_code)) tcp_on_ = *k;
  if (auto k = machine_m_code(machine.tcp_off_code)) tcp_off_ = *k;
  const auto& codes = work_offset_codes();
  for (size_t i = 0; i < codes.size(); ++i) {
    const auto it = options.work_offsets.find(codes[i]);
    if (it == options.work_offsets.end()) continue;
    st_.offsets[i] = it->second;
    st_.defined[i] = true;
  }
  st_.tool = st_.pending_tool = options.start_tool;
  if (options.start) {
    const Axes off = offset();
    for (int a = 0; a < 6; ++a) st_.pos[size_t(a)] = options.start->axis(a) - off[size_t(a)];
    st_.axes.fill(AxisState::Set);
  }
}

void Reader::check_length(std::string_view raw, int number) const {
  if (raw.size() > kMaxLineLength)
    throw InputError(file_, number, "", "a line of " + std::to_string(raw.size()) + " characters: LinuxCNC reads at most " +
                                            std::to_string(kMaxLineLength) + " (\"Command too long\")");
}

// The code of a line (upper case, without blanks and comments); nullopt for a line not read (block delete,
// the "%" lines, what follows the end).
std::optional<std::string> Reader::code_of(std::string_view raw, int number) {
  if (st_.ended) return std::nullopt;
  check_length(raw, number);
  std::string_view view = raw;
  while (!view.empty() && std::isspace(static_cast<unsigned char>(view.front()))) view.remove_prefix(1);
  bool slash = false;
  if (!view.empty() && view.front() == '/') {
    if (options_.block_delete) return std::nullopt;
    view.remove_prefix(1);
    slash = true;
  }
  if (!view.empty() && view.front() == '%') {
    if (slash) throw InputError(file_, number, "%", "a '%' line cannot be block-deleted ('/%'); rs274 refuses it");
    // RS274/NGC: a program opened by "%" (before any other line but blank ones) ends at the next "%";
    // what follows is not read. Anywhere else LinuxCNC refuses it ("Bad character '%' used").
    if (st_.percent) st_.ended = true;
    else if (st_.started && static_cast<size_t>(number) <= main_lines_)
      throw InputError(file_, number, "%", "a '%' line inside the program: '%' only opens a program, on its first line, and ends it");
    st_.percent = true;
    return std::nullopt;
  }
  if (!view.empty()) st_.started = true;
  return strip_line(view, file_, number);
}

void Reader::execute(const std::string& code, int number) {
  line_ = number;
  const ParsedLine parsed = parse_line(code, file_, number, *this);
  set_parameters(parsed.settings, number);  // after the whole line is read, before it runs (as LinuxCNC)
  if (!parsed.words.empty()) block(parsed.words, number);
}

// One warning per distinct code and message: "file:line: CODE message".
void Reader::warn(int line, const std::string& code, const std::string& what) {
  const std::string key = code + what;
  if (!warned_.insert(key).second) return;
  const auto [file, file_line] = source_of(line);
  program_.warnings.push_back(file + ":" + std::to_string(file_line) + ": " + key);
}

namespace {

// The modal group of a G or M code that may appear once per block (LinuxCNC refuses two of a group);
// -1 for the others (the motion and non-modal groups are checked in Reader::block).
int modal_group(char letter, int key) {
  if (letter == 'M') return key == 30 || key == 40 || key == 50 ? 107 : -1;  // spindle
  if (key == 170 || key == 180 || key == 190) return 2;
  if (key == 200 || key == 210) return 6;
  if (key == 900 || key == 910) return 3;
  if (key == 901 || key == 911) return 4;
  if (key == 930 || key == 940 || key == 950) return 5;
  if (key == 980 || key == 990) return 10;
  if (key == 400 || key == 410 || key == 411 || key == 420 || key == 421) return 7;
  if (key == 960 || key == 970) return 14;
  if (key == 70 || key == 80) return 15;
  if (key == 430 || key == 431 || key == 432 || key == 434 || key == 490) return 8;
  if (key >= 540 && key <= 593) return 12;
  if (key == 610 || key == 611 || key == 640) return 13;
  return -1;
}

void check_modal_groups(const std::vector<int>& gs, const std::vector<int>& ms, const std::string& file, int line) {
  std::vector<std::pair<int, int>> seen;  // group, code key
  auto check = [&](char letter, int key) {
    const int g = modal_group(letter, key);
    if (g < 0) return;
    for (const auto& [group, other] : seen)
      if (group == g)
        throw InputError(file, line, code_name(letter, key),
                         "two codes of one modal group in a block (" + code_name(letter, other) + " and " +
                             code_name(letter, key) + ")");
    seen.push_back({g, key});
  };
  for (int g : gs) check('G', g);
  for (int m : ms) check('M', m);
}

}  // namespace

void Reader::block(const std::vector<Word>& words, int line) {
  Values val;
  std::vector<int> gs, ms;
  sort_words(words, line, val, gs, ms);
  check_modal_groups(gs, ms, file_, line);
  std::optional<int> motion, nonmodal;
  bool g53 = false, dwell = false;
  for (int g : gs) {
    if (is_motion_code(g)) {
      // LinuxCNC lets G80 share a block with another motion code (Fanuc posts write "G0 G80 Z50"): the
      // other one is the block's motion.
      if (motion && g != 800 && *motion != 800)
        throw InputError(file_, line, code_name('G', g), "two motion codes in one block");
      if (!motion || *motion == 800) motion = g;
    } else if (is_nonmodal_axis_code(g) || g == 281 || g == 301 || g == 921 || g == 922 || g == 923) {
      if (nonmodal) throw InputError(file_, line, code_name('G', g), "two codes of the non-modal group in one block");
      nonmodal = g;
    } else if (g == 530) {
      g53 = true;
    } else if (g == 40) {
      dwell = true;
    }
  }
  bool axis_words = val.polar();
  for (char c : std::string_view("XYZABC")) axis_words |= val.has(c);
  const bool axes_taken = nonmodal && is_nonmodal_axis_code(*nonmodal);
  if (axes_taken && motion && axis_words && *motion != 800)
    throw InputError(file_, line, code_name('G', *nonmodal), "a motion code and " + code_name('G', *nonmodal) +
                                                                 " both use the axis words of this block");

  apply_units_and_feed_mode(gs, line);  // before F: its units
  apply_feed_speed_tool(val, line);
  apply_m_codes(ms, val, line);         // M6 before G43: G43 without H takes the new tool
  if (dwell) {
    if (!val.has('P')) throw InputError(file_, line, "G4", "dwell without P (seconds)");
    if (*val['P'] < 0) throw InputError(file_, line, val.word('P'), "negative dwell");
    st_.dwell += *val['P'];
  }
  // Before the block's codes: LinuxCNC checks the polar words when it reads the block, in the plane then
  // in force.
  if (val.polar()) check_polar(val, axes_taken ? nonmodal : std::nullopt, g53, line);
  apply_modal_g_codes(gs, val, line);
  if (nonmodal) {
    if (*nonmodal == 100) g10(val, line);
    else if (*nonmodal == 280 || *nonmodal == 300) reference_return(*nonmodal, val, line);
    else if (*nonmodal == 281 || *nonmodal == 301) warn(line, code_name('G', *nonmodal), " stores the reference position: not simulated");
    else set_g92(*nonmodal, val, line);
  }
  check_unused_words(motion, nonmodal, axis_words && !axes_taken, gs, ms, val, line);
  if (motion || (axis_words && !axes_taken)) {
    const int mode = motion.value_or(st_.motion);
    if (!is_cycle(mode)) st_.cycle_il_flag = false;  // the initial level of a series of cycles ends
    if (mode == 800) {
      st_.motion = 800;  // no motion mode: axis words are refused until G0 ... G3 or a cycle
      if (axis_words && !axes_taken)
        throw InputError(file_, line, "G80", "axis words with G80 in force (no motion mode; LinuxCNC refuses them)");
    } else if (axis_words && !axes_taken) {
      if (mode == kNoMotion)
        throw InputError(file_, line, "G", "axis words with no motion mode in force (G0, G1, G2, G3 or a cycle)");
      if (is_cycle(mode)) {
        if (g53) throw InputError(file_, line, "G53", "G53 cannot modify a canned cycle");
        refuse_compensated(line);
        canned_cycle(mode, val, line);
      } else if (mode == 50 || mode == 51) {
        if (g53) throw InputError(file_, line, "G53", "G53 cannot be used with a spline");
        spline(mode, val, line);
      } else {
        refuse_compensated(line);
        motion_block(mode, g53, val, line);
      }
      if (mode != 50 && mode != 51) st_.motion = mode;  // a spline leaves the motion mode as it was (LinuxCNC)
    } else if (motion && (*motion == 20 || *motion == 30) && !axis_words && !axes_taken) {
      refuse_compensated(line);
      motion_block(*motion, g53, val, line);  // G2/G3 with a centre and no axis words: a full circle
      st_.motion = *motion;
    } else {
      if (is_cycle(mode)) throw InputError(file_, line, code_name('G', mode), "canned cycle without axis words");
      if (mode == 50 || mode == 51) throw InputError(file_, line, code_name('G', mode), "spline without its end (X, Y)");
      st_.motion = mode;
    }
  } else if (g53) {
    throw InputError(file_, line, "G53", "G53 without axis words");
  }
  for (int m : ms)
    if (m == 20 || m == 300 || m == 990) st_.ended = true;
}

// A word the block has nothing to use for is refused, as LinuxCNC does ("I word with no G2 or G3 to use
// it"), rather than ignored: "G1 X5 R3" was probably meant as an arc, "G1 X5 P2" as a dwell or a helix.
// I J K belong to an arc, R to an arc, a cycle, G10 or M19; P, Q, L, H and D to the codes
// RS274/NGC gives them (checked against LinuxCNC's rs274). An arc's centre offset across its plane (K in
// G17) is refused too, and S must not be negative.
void Reader::check_unused_words(const std::optional<int>& motion, const std::optional<int>& nonmodal, bool moves,
                                const std::vector<int>& gs, const std::vector<int>& ms, const Values& val,
                                int line) const {
  const int mode = motion ? *motion : moves ? st_.motion : kNoMotion;
  const bool arc = mode == 20 || mode == 30;
  const bool cycle = is_cycle(mode);
  const bool g10 = nonmodal && *nonmodal == 100;
  auto any_of = [](const std::vector<int>& codes, std::initializer_list<int> keys) {
    return std::find_first_of(codes.begin(), codes.end(), keys.begin(), keys.end()) != codes.end();
  };
  auto has_g = [&](std::initializer_list<int> keys) { return any_of(gs, keys); };
  auto has_m = [&](std::initializer_list<int> keys) { return any_of(ms, keys); };
  // A user M code (M100-M199) takes P and Q; so may one the reader does not know (a remapped code, warned
  // about and ignored with its words).
  const bool user_m = std::any_of(ms.begin(), ms.end(), [&](int m) {
    return (m >= 1000 && m <= 1990) || !known_m_code(m) || (tcp_on_ && m == *tcp_on_) || (tcp_off_ && m == *tcp_off_);
  });
  auto refuse = [&](char c, const std::string& users) {
    throw InputError(file_, line, val.word(c), std::string(1, c) + " word with no " + users + " to use it");
  };
  const bool synced = mode == 330 || mode == 331;  // G33, G33.1: K is the distance per turn, I G33.1's retract speed
  const bool spline = mode == 50 || mode == 51;     // G5, G5.1: I J (and G5's P Q) place the control points
  if (val.has('I') && !arc && !spline && mode != 331) refuse('I', "G2, G3, G5, G5.1 or G33.1");
  if (val.has('J') && !arc && !spline) refuse('J', "G2, G3, G5 or G5.1");
  if (val.has('K') && !arc && !synced) refuse('K', "G2, G3, G33 or G33.1");
  if (synced && val.has('F'))
    throw InputError(file_, line, val.word('F'), "F word with " + code_name('G', mode) + " (its feed is K per spindle turn)");
  if (val.has('R') && !arc && !cycle && !g10 && !has_m({190}) && !has_g({411, 421}))
    refuse('R', "G2, G3, canned cycle, G10, G41.1, G42.1 or M19");
  const bool dwell_cycle = mode == 820 || mode == 840 || mode == 740 || mode == 860 || mode == 880 || mode == 890;
  if (val.has('P') && !arc && !dwell_cycle && !g10 && !user_m && mode != 50 && !has_g({40, 640}) &&
      !has_m({190, 500, 510, 520, 530, 620, 630, 640, 650, 660, 980}))
    refuse('P', "G2, G3, G4, G5, G10, G64, G74, G82, G84, G86, G89, M19, M50-M53, M62-M66 or user M code");
  if (val.has('Q') && mode != 830 && mode != 730 && mode != 50 && !g10 && !user_m && !has_g({640}) &&
      !has_m({190, 610, 660, 670, 680}))
    refuse('Q', "G5, G10, G64, G73, G83, M19, M61, M66-M68 or user M code");
  // G74 takes no repeats in LinuxCNC, and G41.1/G42.1 an L (the orientation) only in the G18 plane.
  if (val.has('L') && !g10 && !(cycle && mode != 740) && !has_g({410, 420}) && !(has_g({411, 421}) && st_.plane == 18) &&
      !has_m({660, 980}))
    refuse('L', "G10, canned cycle but G74, G41, G42, G41.1/G42.1 in G18, or M66");
  if (has_m({190}) && val.has('P') && !(*val['P'] == 0 || *val['P'] == 1 || *val['P'] == 2))
    throw InputError(file_, line, val.word('P'), "M19's P (the direction) must be 0, 1 or 2");
  if (val.has('H') && !has_g({430, 432, 434})) refuse('H', "G43, G43.2 or G43.4");
  if (val.has('D') && !has_g({410, 411, 420, 421, 960})) refuse('D', "G41, G41.1, G42, G42.1 or G96");
  if (arc) {
    const char across = st_.plane == 17 ? 'K' : st_.plane == 18 ? 'J' : 'I';
    if (val.has(across))
      throw InputError(file_, line, val.word(across),
                       std::string(1, across) + " word given for an arc in the G" + std::to_string(st_.plane) + " plane");
  }
  if (val.has('S') && *val['S'] < 0) throw InputError(file_, line, val.word('S'), "negative spindle speed");
}

// The block's G and M codes (as code keys, in their order) and its value words by letter; N and O are
// ignored. Throws on a letter the machine or the reader does not know and on a word given twice.
void Reader::sort_words(const std::vector<Word>& words, int line, Values& val, std::vector<int>& gs,
                        std::vector<int>& ms) const {
  bool io = false;  // M66-M68 take an E word (and G76, refused as a cycle the reader does not run)
  for (const Word& w : words)
    if ((w.letter == 'M' && (w.value == 66 || w.value == 67 || w.value == 68)) || (w.letter == 'G' && w.value == 76))
      io = true;
  const Word* previous = nullptr;
  for (const Word& w : words) {
    if (w.letter == 'G') { gs.push_back(code_key(w, file_, line)); previous = &w; continue; }
    if (w.letter == 'M') { ms.push_back(code_key(w, file_, line)); previous = &w; continue; }
    if (w.letter == 'N' && &w != &words.front())  // rs274: "Bad character 'n' used"
      throw InputError(file_, line, w.text, "a line number N must begin the line");
    if (w.letter == 'N' || w.letter == 'O') { previous = &w; continue; }
    if (w.letter == 'E' && !io)
      throw InputError(file_, line, previous ? previous->text + w.text : w.text,
                       "numbers have no exponent in RS274/NGC: E is a word, read only with M66-M68");
    if (std::string_view("XYZABC").find(w.letter) != std::string_view::npos && !machine_.has_axis(w.letter))
      throw InputError(file_, line, w.text,
                       "machine '" + machine_.name + "' has no " + std::string(1, w.letter) + " axis (axes: XYZ" +
                           machine_.rotary_axes() + ")");
    if (std::string_view("UVW").find(w.letter) != std::string_view::npos)
      throw InputError(file_, line, w.text, "machine '" + machine_.name + "' has no " + std::string(1, w.letter) + " axis");
    if (std::string_view("XYZABCIJKRFSTPQHDLE@^").find(w.letter) == std::string_view::npos)
      throw InputError(file_, line, w.text, "unknown word letter");
    const size_t k = Values::slot(w.letter);
    if (val.value[k]) throw InputError(file_, line, w.text, "word given twice in one block");
    val.value[k] = w.value;
    val.text[k] = w.text;
    previous = &w;
  }
}

// Feed mode (G93, G94) and length units (G20, G21), which F needs. (RS274/NGC sets the units after F and
// converts the feed; taking F in the block's new units gives the same feed.)
void Reader::apply_units_and_feed_mode(const std::vector<int>& gs, int line) {
  for (int g : gs) {
    switch (g) {
      case 930: st_.inverse_time = true; break;
      case 940: st_.inverse_time = false, st_.feed = st_.feed_word = 0.0; break;  // RS274/NGC: G94 clears the feed rate
      case 950: throw InputError(file_, line, "G95", "feed per revolution is not supported");
      case 200: st_.inch = true; break;
      case 210: st_.inch = false; break;
      default: break;
    }
  }
}

// A move with cutter radius compensation on and an offset: the compensated path (LinuxCNC's corner arcs
// and intersections) is not simulated, and the programmed one would be off by the tool's radius.
void Reader::refuse_compensated(int line) const {
  if (st_.comp_offset.empty()) return;
  throw InputError(file_, line, st_.comp_offset,
                   "cutter radius compensation is not simulated: the tool would run off the programmed path (post "
                   "the tool-centre path, or compensate with D0)");
}

// The other modal settings of the block's G codes (all but the motion and non-modal groups), in
// RS274/NGC's order of execution: plane, cutter compensation, tool length, coordinate system, path
// control, distance mode, retract mode.
void Reader::apply_modal_g_codes(const std::vector<int>& gs, const Values& val, int line) {
  for (int g : gs) {
    switch (g) {
      case 170: case 180: case 190:
        if (st_.cutter_comp && g / 10 != st_.plane)
          throw InputError(file_, line, code_name('G', g), "cannot change planes with cutter compensation on");
        st_.plane = g / 10;
        break;
      default: break;
    }
  }
  for (int g : gs) {  // cutter compensation, after the plane (RS274/NGC's order)
    if (g == 400) st_.cutter_comp = false, st_.comp_offset.clear();
    if (g != 410 && g != 411 && g != 420 && g != 421) continue;
    if (st_.cutter_comp) throw InputError(file_, line, code_name('G', g), "cutter compensation is already on (G40 first)");
    if (st_.plane == 19) throw InputError(file_, line, code_name('G', g), "cutter compensation only in the G17 and G18 planes");
    st_.cutter_comp = true;
    // G41/G42 D n: tool n's radius (no D: the tool in the spindle); G41.1/G42.1 D: the diameter. D0 is none.
    const auto d = val['D'];
    if (d && *d == 0.0) continue;
    st_.comp_offset = code_name('G', g);
    if (d) st_.comp_offset.append(1, ' ').append(val.word('D'));
  }
  for (int g : gs)
    if (g == 960 && !val.has('S')) throw InputError(file_, line, "G96", "S (the surface speed) missing");
  for (int g : gs)
    if (g == 430 || g == 431 || g == 432 || g == 434 || g == 490) tool_length_offset(g, val, line);
  for (int g : gs)
    if (g >= 540 && g <= 593) select_coordinate_system(g, line);
  for (int g : gs) {
    switch (g) {
      case 610: case 611: case 640: break;  // path control: no effect on the swept volume
      case 900: st_.incremental = false; break;
      case 910: st_.incremental = true; break;
      case 901: st_.arc_incremental = false; break;
      case 911: st_.arc_incremental = true; break;
      case 980: st_.retract_r_plane = false; break;
      case 990: st_.retract_r_plane = true; break;
      default: break;
    }
  }
  for (int g : gs) {
    if (g == 870 || g == 880)
      throw InputError(file_, line, code_name('G', g), "back boring and manual-retract cycles are not supported");
    if (g == 52 || g == 53) throw InputError(file_, line, code_name('G', g), "NURBS (G5.2, G5.3) are not supported");
    if (g == 160)
      throw InputError(file_, line, "G16", "Fanuc's polar coordinate mode is not supported (LinuxCNC's @ and ^ words are)");
    if (g == 70) throw InputError(file_, line, "G7", "lathe diameter mode is not supported");
    if (g == 171 || g == 181 || g == 191)
      throw InputError(file_, line, code_name('G', g), "the U V W planes are not supported");
    if (g == 760) throw InputError(file_, line, "G76", "the lathe threading cycle is not supported");
    if (g == 700 || g == 710 || g == 711 || g == 712 || g == 720 || g == 721 || g == 722)
      throw InputError(file_, line, code_name('G', g), "lathe cycles (G70-G72) are not supported");
    if (g >= 382 && g <= 385) throw InputError(file_, line, code_name('G', g), "probing is not supported");
    if (recognised(g)) continue;
    // Its axis words would run in the motion mode in force (a remapped cycle, polar coordinates).
    for (char c : std::string_view("XYZABC"))
      if (val.has(c)) throw InputError(file_, line, code_name('G', g), "unknown code with axis words");
    warn(line, code_name('G', g), " unknown code ignored");
  }
}

// F, S and T words (in the units after this block's G20/G21).
void Reader::apply_feed_speed_tool(const Values& val, int line) {
  if (val.has('F')) {
    const double f = *val['F'];
    if (f < 0) throw InputError(file_, line, val.word('F'), "negative feed");
    st_.feed = st_.inverse_time ? f : f * unit();
    st_.feed_word = f;
  }
  if (val.has('S')) st_.spindle = *val['S'];
  if (val.has('T')) {
    const double t = *val['T'];
    if (t < 0 || t > 99999 || t != std::floor(t)) throw InputError(file_, line, val.word('T'), "not a tool number");
    st_.pending_tool = static_cast<int>(t);
  }
}

void Reader::set_tcp(bool on, bool g434) {
  if (on != st_.tcp && !program_.blocks.empty() && !convert_position_for_tcp(on)) st_.tcp_switched = true;
  st_.tcp = on;
  st_.tcp_g434 = g434;
}

// The block's M codes but the stops (which act after its motion); the machine's own TCP codes first.
void Reader::apply_m_codes(const std::vector<int>& ms, const Values& val, int line) {
  for (int m : ms) {
    if (tcp_on_ && m == *tcp_on_) { set_tcp(true, false); continue; }
    if (tcp_off_ && m == *tcp_off_) { set_tcp(false, false); continue; }
    switch (m) {
      case 30: st_.spindle_dir = 1; break;
      case 40: st_.spindle_dir = -1; break;
      case 50: st_.spindle_dir = 0; break;
      case 60:  // tool change: the selected tool goes into the spindle
        st_.tool = st_.pending_tool;
        st_.empty_spindle = st_.tool == 0 && !options_.tool_lengths.empty();
        st_.tool_line = line;
        break;
      case 610: {  // set the tool number without a change
        if (!val.has('Q') || *val['Q'] < 0 || *val['Q'] != std::floor(*val['Q']) || *val['Q'] > 99999)
          throw InputError(file_, line, "M61", "needs Q, a tool number");
        st_.tool = static_cast<int>(*val['Q']);
        st_.empty_spindle = st_.tool == 0 && !options_.tool_lengths.empty();
        st_.tool_line = line;
        break;
      }
      case 1280: set_tcp(true, false); break;
      case 1290: set_tcp(false, false); break;
      case 980:  // a call opens its line (programs.cpp); in a block LinuxCNC knows no M98
        throw InputError(file_, line, "M98", "M98 must open its line (after an optional N number), as LinuxCNC reads a call");
      case 990:
        if (!calls_.empty())  // a return stands alone (programs.cpp)
          throw InputError(file_, line, "M99", "M99 in a block with other words cannot return from a subprogram (LinuxCNC refuses it)");
        warn(line, "M99", " in the main program ends it here: LinuxCNC's controller would run it again from the start, endlessly");
        break;
      case 20: case 300: case 0: case 10: case 600: break;  // stops, after the motion
      case 70: case 80: case 90: case 480: case 490: case 500: case 510: case 520: case 530: break;  // coolant, overrides
      case 190: break;  // spindle orientation: the swept volume does not depend on it
      case 660: case 670: case 680: case 620: case 630: case 640: case 650:
        warn(line, code_name('M', m), " I/O is not simulated");
        break;
      default: warn(line, code_name('M', m), " unknown code ignored");
    }
  }
}

}  // namespace gcode

GcodeOptions gcode_options(const Scene& scene) {
  GcodeOptions o;
  o.work_offsets = scene.work_offsets;
  o.tool_length = scene.tool.length;
  for (const ToolEntry& e : scene.tools) o.tool_lengths[e.number] = e.tool.length;
  o.start_tool = scene.tool_number;
  return o;
}

Program parse_gcode(std::string_view text, const std::string& file, const MachineSpec& machine, const GcodeOptions& options) {
  // rs274 stops at it ("Bad character '\357' used"); the message had named a field of mojibake.
  if (starts_with_utf8_bom(text))
    throw InputError(file, 1, "", "starts with a UTF-8 byte-order mark, which LinuxCNC refuses; save the program without it");
  gcode::Reader reader(file, machine, options);
  reader.run(gcode::split_lines(text));
  return reader.finish();
}

Program read_gcode(const std::filesystem::path& file, const MachineSpec& machine, const GcodeOptions& options) {
  GcodeOptions with_dir = options;
  const std::filesystem::path dir = file.parent_path();
  with_dir.subroutine_dirs.insert(with_dir.subroutine_dirs.begin(), dir.empty() ? std::filesystem::path(".") : dir);
  return parse_gcode(read_text_file(file, "G-code file"), file.string(), machine, with_dir);
}

}  // namespace tf
