// Profile parsing and bad input: each error names the file and the element's line; the CLI exits 2.
#include <gmock/gmock.h>

#include <cstdlib>
#include <functional>
#include <random>

#include "offset_test_util.hpp"
#include "tiltfield/core/error.hpp"

namespace tf::offset::test {
namespace {

int line_of(const std::string& text) {
  try {
    validate_profile(parse_profile(text, "p.txt"));
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "p.txt");
    return e.line();
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return -1;
}

TEST(OffsetParse, ReadsLinesArcsAndLongArcs) {
  const Profile p = parse_profile("# comment\nSTART 1 2\n0 10 0\n5 0 10 LONG\n0 -10 0\n-5 0 -10\n", "p");
  ASSERT_EQ(p.elements.size(), 4u);
  EXPECT_EQ(p.elements[0].line, 3);
  EXPECT_FALSE(p.elements[0].is_arc());
  EXPECT_NEAR(p.elements[1].sweep, M_PI, 1e-12);  // chord == 2R: half circle either way
  EXPECT_NEAR(p.elements[3].sweep, -M_PI, 1e-12);
  const Profile q = parse_profile("START 0 0\n0 10 0\n10 0 10\n10 -10 0 LONG\n0 0 -10\n", "q");
  EXPECT_NEAR(q.elements[1].sweep, M_PI / 3, 1e-12);  // chord 10, R 10: 60 degrees
  EXPECT_GT(std::abs(q.elements[2].sweep), M_PI);
  // The arc's centre: R > 0 turns left, the short arc's centre on the chord's left.
  EXPECT_LE((q.elements[1].c - Eigen::Vector2d(10 - std::sqrt(75.0), 5)).norm(), 1e-12);
}

// A half circle written in decimals has its chord a hair longer than 2|R| (R 1.41421356 over (2, 2): by
// 7.5e-9); it was refused. A byte-order mark before START is skipped (both black-box testing).
TEST(OffsetParse, DecimalHalfCircleAndByteOrderMark) {
  const Profile p = parse_profile("\xEF\xBB\xBFSTART 0 0\n0 2 2\n1.41421356 -2 -2\n", "p");
  ASSERT_EQ(p.elements.size(), 2u);
  const Segment& arc = p.elements[1];
  EXPECT_NEAR(std::abs(arc.sweep), M_PI, 1e-7);
  EXPECT_NEAR((arc.a - arc.c).norm(), arc.r, 1e-12);
  EXPECT_NEAR((arc.b - arc.c).norm(), arc.r, 1e-12);
  EXPECT_EQ(line_of("START 0 0\n0 2 2\n1.4142 -2 -2\n"), 3);  // 2.8e-4 longer: a wrong radius
}

TEST(OffsetParse, RoundTripsThroughFormat) {
  const Profile p = scene_profile("blade_section.txt");
  const Profile q = parse_profile(format_profile(p), "again");
  ASSERT_EQ(q.elements.size(), p.elements.size());
  for (size_t k = 0; k < p.elements.size(); ++k) {
    EXPECT_LE((q.elements[k].a - p.elements[k].a).norm(), 1e-8);
    EXPECT_NEAR(q.elements[k].sweep, p.elements[k].sweep, 1e-8);
  }
}

TEST(OffsetParse, BadInputNamesTheLine) {
  EXPECT_EQ(line_of("START 0 0\n0 10 0\n4 0 10\n0 -10 0\n0 0 -10\n"), 3);        // chord 10 > 2|R| = 8
  EXPECT_EQ(line_of("START 0 0\n0 10 0\n0 0 10\n0 -10 0\n0 0 -9\n"), 5);         // not closed
  EXPECT_EQ(line_of("START 0 0\n0 10 10\n0 -10 0\n0 10 -10\n0 -10 0\n"), 4);     // bow tie: crosses itself
  EXPECT_EQ(line_of("START 0 0\n0 10 0\n0 0 1o\n0 -10 0\n0 0 -10\n"), 3);        // garbage number
  EXPECT_EQ(line_of("START 0 0\n0 10 0\n0 0 10 SHORT\n"), 3);                     // unknown word
  EXPECT_EQ(line_of("START 0 0\n0 10 0\n0 0 0\n0 -10 0\n"), 3);                   // zero length
  EXPECT_EQ(line_of("START 0 0\n0 10 0\n0 0 1e-12\n0 0 10\n0 -10 0\n0 0 -10\n"), 3);  // below 1e-6 mm
  EXPECT_EQ(line_of("START 0 0\n0 10 0\n0 -10 0\n"), 3);                          // reverses onto itself
  EXPECT_EQ(line_of("0 10 0\n"), 1);                                              // no START
  EXPECT_EQ(line_of("START 0 0 0\n"), 1);
  EXPECT_EQ(line_of("START 0 nan\n"), 1);
  EXPECT_EQ(line_of("START 0 0\n0 1e999 0\n"), 2);
  EXPECT_EQ(line_of(""), 0);                                                      // empty file
  EXPECT_EQ(line_of("START 0 0\n"), 1);                                           // no elements
}

// A number beyond a kilometre is refused as such, not as the "self-crossing" profile it made before.
TEST(OffsetParse, CoordinatesBeyondAKilometreAreNamed) {
  auto message = [](const std::string& text) {
    try {
      parse_profile(text, "p.txt");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_THAT(message("START 0 0\n0 1e300 0\n0 -1e300 1\n0 0 -1\n"), ::testing::HasSubstr("p.txt:2: field 'DX': the value 1e+300"));
  EXPECT_THAT(message("START 2e6 0\n0 1 0\n"), ::testing::HasSubstr("p.txt:1: field 'x'"));
  EXPECT_THAT(message("START 0 0\n5e6 1 0\n"), ::testing::HasSubstr("p.txt:2: field 'R'"));
  EXPECT_THAT(message("START 0 0\n0 900000 0\n0 900000 0\n0 -1800000 1\n"),
              ::testing::HasSubstr("p.txt:3: field 'DX': the element's end x 1.8e+06"));
  EXPECT_EQ(message("START 0 0\n0 900000 0\n0 0 1\n0 -900000 0\n0 0 -1\n"), "accepted");  // 900 m: kept
}

// A gap law's values have the profile's bound: a gap of 1e7 took 55 s and 4 GB, 1e12 ended in bad_alloc.
TEST(OffsetParse, GapLawValuesBeyondAKilometreAreNamed) {
  auto where = [](const std::string& csv) {
    const std::string file = write_temp("law.csv", csv);
    try {
      read_gap_law(file);
    } catch (const InputError& e) {
      return std::to_string(e.line()) + " " + e.field();
    }
    return std::string("accepted");
  };
  EXPECT_EQ(where("s,gap\n0,0.5\n100,1e7\n"), "3 gap");
  EXPECT_EQ(where("s,gap\n-2e6,0.5\n100,1\n"), "2 s");
  EXPECT_EQ(where("s,gap\n0,0.5\n100,1000\n"), "accepted");
  // A directory is named as one (it read as an empty file).
  const std::filesystem::path dir = std::filesystem::path(write_temp("law.csv", "")).parent_path();
  for (auto read : {std::function<void()>([&] { read_gap_law(dir); }), std::function<void()>([&] { read_profile(dir); })}) {
    try {
      read();
      ADD_FAILURE() << "a directory accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
    }
  }
}

// Feeds random and mutated profile texts to the parser: it only ever returns or throws InputError.
TEST(OffsetParse, FuzzOnlyReturnsOrThrowsInputError) {
  std::mt19937 rng(7);
  const std::string seeds[] = {format_profile(scene_profile("blade_section.txt")),
                               format_profile(scene_profile("die_section.txt")), "START 0 0\n0 1 0\n1 0 1\n"};
  const std::string alphabet = "0123456789.-+eE \n\tSTARTLONG#,xnaif";
  int parsed = 0, rejected = 0;
  for (int it = 0; it < 3000; ++it) {
    std::string s = seeds[it % 3];
    const int edits = 1 + static_cast<int>(rng() % 6);
    for (int e = 0; e < edits; ++e) {
      const size_t pos = s.empty() ? 0 : rng() % s.size();
      switch (rng() % 4) {
        case 0: if (!s.empty()) s[pos] = alphabet[rng() % alphabet.size()]; break;
        case 1: s.insert(pos, 1, alphabet[rng() % alphabet.size()]); break;
        case 2: if (!s.empty()) s.erase(pos, 1 + rng() % 5); break;
        default: s.insert(pos, 1, static_cast<char>(rng() % 256)); break;
      }
    }
    try {
      Profile p = parse_profile(s, "fuzz");
      validate_profile(p);
      GapLaw law = constant_gap(0.05 + (rng() % 100) * 0.01);
      OffsetOptions o;
      o.side = rng() % 2 ? Side::Inside : Side::Outside;
      (void)offset_profile(p, law, o);  // valid input must offset without throwing
      ++parsed;
    } catch (const InputError&) {
      ++rejected;
    }
  }
  EXPECT_GT(rejected, 0);
  EXPECT_GT(parsed + rejected, 0);
}

// The command line: exit 2, one line naming file and line, no output file.
TEST(OffsetParse, CommandLineExitsTwoWithTheLine) {
  const auto bad = write_temp("chord.txt", "START 0 0\n0 10 0\n4 0 10\n0 -10 0\n0 0 -10\n");
  const auto out = std::filesystem::path(bad).parent_path() / "bad_out.ngc";
  const auto err = std::filesystem::path(bad).parent_path() / "stderr.txt";
  const std::string cmd = std::string(TILTFIELD_EXE) + " offset " + bad + " -d 1 -o " + out.string() + " 2> " + err.string();
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  EXPECT_FALSE(std::filesystem::exists(out));
  std::ifstream in(err);
  std::string line;
  std::getline(in, line);
  EXPECT_THAT(line, ::testing::HasSubstr("chord.txt:3"));
  const auto empty = write_temp("empty.txt", "");
  EXPECT_EQ(WEXITSTATUS(std::system((std::string(TILTFIELD_EXE) + " offset " + empty + " -d 1 -o " + out.string() +
                                     " 2>/dev/null").c_str())),
            2);
  EXPECT_EQ(WEXITSTATUS(std::system((std::string(TILTFIELD_EXE) + " offset " + scene_file("rounded_rect.txt") +
                                     " -d -1 -o " + out.string() + " 2>/dev/null").c_str())),
            2);
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace tf::offset::test
