// tiltfield tests: programs for the simulation's tests, built block by block as a controller runs them,
// without the G-code reader (the tests of a library link that library only). Each call adds one block on
// the next line (line k for the k-th block); axes a block does not give keep their value, as in G-code.
// Like the reader without a start position, each axis starts where the program first puts it.
#pragma once
#include <optional>

#include "tiltfield/core/program.hpp"

namespace tf::test {

struct Axes {
  std::optional<double> x = {}, y = {}, z = {}, a = {}, b = {}, c = {};  // mm, deg
};

class Moves {
 public:
  Moves& rapid(const Axes& to) { return add(Motion::Rapid, to, FeedMode::PerMinute, 0.0); }
  // G94 G1 at `feed` mm/min.
  Moves& line(const Axes& to, double feed) { return add(Motion::Linear, to, FeedMode::PerMinute, feed); }
  // G1 at the previous block's feed and feed mode.
  Moves& line(const Axes& to) { return add(Motion::Linear, to, mode_, feed_); }
  // G17 G2 (`clockwise`) or G3 about `centre` (X Y; Z the arc's own), at the previous block's feed.
  Moves& arc(const Axes& to, double cx, double cy, bool clockwise) {
    add(clockwise ? Motion::ArcCW : Motion::ArcCCW, to, mode_, feed_);
    program_.blocks.back().arc_center = {cx, cy, at_.z};
    return *this;
  }
  // G93 G1: `per_minute` is 1 / the block's time in minutes.
  Moves& inverse_time(const Axes& to, double per_minute) {
    return add(Motion::Linear, to, FeedMode::InverseTime, per_minute);
  }
  // Tool-centre-point control for the blocks that follow (X Y Z are then the tool tip, part frame).
  Moves& tcp(bool on = true) {
    tcp_ = on;
    return *this;
  }

  Program program() const {
    Program p = program_;
    if (!p.blocks.empty()) p.start = first_;
    return p;
  }

 private:
  Moves& add(Motion motion, const Axes& to, FeedMode mode, double feed) {
    Block b;
    b.line = static_cast<int>(program_.blocks.size()) + 1;
    b.motion = motion;
    b.target = at_;
    set(to.x, b.target.x, first_.x, seen_[0]);
    set(to.y, b.target.y, first_.y, seen_[1]);
    set(to.z, b.target.z, first_.z, seen_[2]);
    set(to.a, b.target.a, first_.a, seen_[3]);
    set(to.b, b.target.b, first_.b, seen_[4]);
    set(to.c, b.target.c, first_.c, seen_[5]);
    b.tcp = tcp_;
    b.feed_mode = mode;
    b.feed = feed;
    if (motion != Motion::Rapid) {
      mode_ = mode;
      feed_ = feed;
    }
    at_ = b.target;
    program_.blocks.push_back(b);
    return *this;
  }
  static void set(const std::optional<double>& v, double& target, double& first, bool& seen) {
    if (!v) return;
    target = *v;
    if (!seen) first = *v;
    seen = true;
  }

  Program program_;
  Joints at_, first_;
  bool seen_[6] = {false, false, false, false, false, false};
  bool tcp_ = false;
  FeedMode mode_ = FeedMode::PerMinute;
  double feed_ = 0.0;
};

}  // namespace tf::test
