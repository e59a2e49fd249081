// `rocking animate` of a structure on rocking columns and of one with joints,
// run as a user runs it: a GIF, and frame data (the .data folder beside it)
// that draw each column turned about its pivot corner by the columns' angle,
// the cap beam moved onto their tops, and each segment turned about the
// corner the segment below carries, at the angles of `rocking simulate`'s
// history row of the same time (read by column name).
#include <doctest/doctest.h>
#include "close.hpp"
#include "csv_table.hpp"
#include "run_program.hpp"
#include "temp_path.hpp"
#include <cctype>
#include <cmath>
#include <complex>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;
using cli::Result;
using cli::run;

namespace {

using Point = std::pair<double, double>;

// One frame of the frame data: its time and its pieces (the rows between
// blank lines), each with its `part` (the columns read by the block's header).
struct Piece {
  int part = -1;
  std::vector<Point> points;
};
struct Frame {
  double t = -1;
  std::vector<Piece> pieces;
  std::vector<const Piece*> of(int part) const {
    std::vector<const Piece*> out;
    for (const Piece& p : pieces)
      if (p.part == part) out.push_back(&p);
    return out;
  }
};

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

std::vector<Frame> read_frames(const fs::path& file) {
  std::ifstream in(file);
  REQUIRE_MESSAGE(in, file.string());
  std::vector<Frame> frames;
  std::map<std::string, std::size_t> column;  // the current block's header
  Piece piece;
  auto close_piece = [&] {
    if (!piece.points.empty()) {
      REQUIRE(!frames.empty());
      frames.back().pieces.push_back(piece);
    }
    piece = Piece{};
  };
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("# frame ", 0) == 0) {
      close_piece();
      const std::size_t at = line.find("t = ");
      REQUIRE_MESSAGE(at != std::string::npos, line);
      frames.push_back({.t = std::stod(line.substr(at + 4)), .pieces = {}});
    } else if (line.empty()) {
      close_piece();
    } else if (line[0] == '#') {
      continue;
    } else if (std::isalpha(static_cast<unsigned char>(line[0])) != 0) {  // a header
      column.clear();
      const std::vector<std::string> names = words(line);
      for (std::size_t k = 0; k < names.size(); ++k) column[names[k]] = k;
      REQUIRE(column.contains("x"));
      REQUIRE(column.contains("y"));
      REQUIRE(column.contains("part"));
    } else {
      const std::vector<std::string> f = words(line);
      const int part = std::stoi(f.at(column.at("part")));
      if (piece.part != part) close_piece();
      piece.part = part;
      piece.points.emplace_back(std::stod(f.at(column.at("x"))), std::stod(f.at(column.at("y"))));
    }
  }
  close_piece();
  return frames;
}

// The row of a history whose time is t (to the printed digits).
std::size_t row_at(const CsvTable& h, double t) {
  for (std::size_t i = 0; i < h.rows.size(); ++i)
    if (std::abs(std::stod(h.at(i, "t [s]")) - t) <= 1e-9) return i;
  FAIL("no history row at t = " << t);
  return 0;
}

// p turned clockwise by theta about c: (p - c) e^(-i theta) + c.
Point turned(Point p, Point c, double theta) {
  const std::complex<double> z = std::complex<double>(p.first - c.first, p.second - c.second) * std::polar(1.0, -theta);
  return {c.first + z.real(), c.second + z.imag()};
}

void check_point(const Point& drawn, const Point& want, double tol) {
  CHECK(drawn.first == within(want.first, tol));
  CHECK(drawn.second == within(want.second, tol));
}

bool is_gif(const fs::path& file, unsigned width, unsigned height) {
  const std::string g = file_text(file);
  if (g.size() < 10 || g.substr(0, 6) != "GIF89a") return false;
  auto u16 = [&](std::size_t at) { return static_cast<unsigned char>(g[at]) | static_cast<unsigned char>(g[at + 1]) << 8; };
  return static_cast<unsigned>(u16(6)) == width && static_cast<unsigned>(u16(8)) == height;
}

// The frame data print 9 significant digits (coordinates up to 11.1 m: off
// by at most 5e-8 m), the history its angles to 9 (off by 5e-11 rad, 5e-10 m
// at the piers' 9.6 m): a drawn point is within this of where the angle puts it [m].
constexpr double printed = 1e-7;

}  // namespace

TEST_CASE("animate the rocking frame: a GIF whose frames draw both piers turned by the history's columns.theta and the beam on them") {
  const fs::path dir = scratch_dir("animate_frame");
  const std::string scene = std::string(ROCKING_SCENES) + "/rocking_frame.toml";
  const Result r = run("-q animate " + scene + " --duration 1 --fps 10 --frames 11 --size 300x200 --exaggerate-rotation 1 --out " +
                       (dir / "frame.gif").string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK_MESSAGE(cli::contains(r.out, "11 frames"), r.out);
  CHECK(is_gif(dir / "frame.gif", 300, 200));
  // Its labels ask for no Symbol font, which the GIF terminal lacks (it drops such a label): Greek as UTF-8.
  const std::string gp = file_text(dir / "frame.gp");
  CHECK_FALSE(cli::contains(gp, "{/Symbol"));
  CHECK(cli::contains(gp, "set ylabel \"columns θ_c/α_c\""));
  const Result sim = run("-q simulate " + scene + " --duration 1 --every 0.1 --out " + (dir / "run").string());
  REQUIRE_MESSAGE(sim.code == 0, sim.err);
  const CsvTable history = csv_table(file_text(dir / "run" / "history.csv"));
  const std::vector<Frame> frames = read_frames(dir / "frame.data" / "main.dat");
  REQUIRE(frames.size() == 11);
  // The piers: 1.6 m wide, 9.6 m tall, their axes 6 m apart (the scene's [columns]).
  const double b = 0.8, h = 4.8, R = std::hypot(b, h), alpha = std::atan(b / h);
  double peak = 0;
  for (const Frame& f : frames) {
    CAPTURE(f.t);
    const std::size_t i = row_at(history, f.t);
    const double theta = std::stod(history.at(i, "columns.theta [rad]"));
    peak = std::max(peak, std::abs(theta));
    const double s = theta > 0 ? 1 : theta < 0 ? -1 : 0;
    const std::vector<const Piece*> piers = f.of(3), beam = f.of(4);
    REQUIRE(piers.size() == 2);
    REQUIRE(beam.size() == 1);
    for (std::size_t k = 0; k < 2; ++k) {
      const double x = k == 0 ? -3.0 : 3.0;
      const Point pivot{x + s * b, 0.0};
      const std::vector<Point> rest{{x - b, 0}, {x + b, 0}, {x + b, 2 * h}, {x - b, 2 * h}, {x - b, 0}};
      REQUIRE(piers[k]->points.size() == rest.size());
      for (std::size_t c = 0; c < rest.size(); ++c) check_point(piers[k]->points[c], turned(rest[c], pivot, theta), printed);
    }
    // The beam moved by MODEL.md 16's (dx, dy), dx the history's beam.x.
    const double dx = s == 0 ? 0.0 : 2 * R * s * (std::sin(alpha) - std::sin(alpha - s * theta));
    const double dy = s == 0 ? 0.0 : 2 * R * (std::cos(alpha - s * theta) - std::cos(alpha));
    CHECK(std::stod(history.at(i, "beam.x [m]")) == within(dx, printed));
    REQUIRE(beam[0]->points.size() == 2);
    check_point(beam[0]->points[0], {-3.8 + dx, 2 * h + dy}, printed);
    check_point(beam[0]->points[1], {3.8 + dx, 2 * h + dy}, printed);
    // The deck 1.5 m above the beam's centre, upright.
    const std::vector<const Piece*> deck = f.of(0);
    REQUIRE(deck.size() == 1);
    REQUIRE(deck[0]->points.size() == 2);
    check_point(deck[0]->points[1], {dx, 2 * h + dy + 1.5}, printed);
  }
  CHECK(peak > 0.01);  // the frame rocked within the frames checked
}

TEST_CASE("animate the stacked blocks: each block turned about its joint's corner by the history's theta and joint1.theta") {
  const fs::path dir = scratch_dir("animate_stack");
  const std::string scene = std::string(ROCKING_SCENES) + "/stacked_blocks.toml";
  const Result r = run("-q animate " + scene + " --duration 1 --fps 10 --frames 11 --size 300x200 --exaggerate-rotation 1 --out " +
                       (dir / "stack.gif").string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(is_gif(dir / "stack.gif", 300, 200));
  const std::string gp = file_text(dir / "stack.gp");
  CHECK(cli::contains(gp, "column('joint1.theta_over_alpha')"));  // the right trace: every joint's angle
  CHECK_FALSE(cli::contains(gp, "{/Symbol"));
  const Result sim = run("-q simulate " + scene + " --duration 1 --every 0.1 --out " + (dir / "run").string());
  REQUIRE_MESSAGE(sim.code == 0, sim.err);
  const CsvTable history = csv_table(file_text(dir / "run" / "history.csv"));
  const std::vector<Frame> frames = read_frames(dir / "stack.data" / "main.dat");
  REQUIRE(frames.size() == 11);
  // The plinth 0.8 m wide and 1 m tall; the artefact 0.3 m wide, from 1 m to 1.9 m.
  const double B0 = 0.4, B1 = 0.15, h1 = 1.0, top = 1.9;
  double peak = 0;
  for (const Frame& f : frames) {
    CAPTURE(f.t);
    const std::size_t i = row_at(history, f.t);
    const double t0 = std::stod(history.at(i, "theta [rad]")), t1 = std::stod(history.at(i, "joint1.theta [rad]"));
    peak = std::max(peak, std::abs(t1));
    const double s0 = t0 > 0 ? 1 : t0 < 0 ? -1 : 0, s1 = t1 > 0 ? 1 : t1 < 0 ? -1 : 0;
    const std::vector<const Piece*> blocks = f.of(3);
    REQUIRE(blocks.size() == 2);
    const Point p0{s0 * B0, 0.0};
    const std::vector<Point> plinth{{-B0, 0}, {B0, 0}, {B0, h1}, {-B0, h1}, {-B0, 0}};
    for (std::size_t c = 0; c < plinth.size(); ++c) check_point(blocks[0]->points[c], turned(plinth[c], p0, t0), printed);
    // The artefact: its corner on the plinth goes with the plinth, and it turns about that point by t0 + t1 in all.
    const Point q = turned({s1 * B1, h1}, p0, t0);
    const std::vector<Point> artefact{{-B1, h1}, {B1, h1}, {B1, top}, {-B1, top}, {-B1, h1}};
    for (std::size_t c = 0; c < artefact.size(); ++c) {
      const Point moved{artefact[c].first - s1 * B1 + q.first, artefact[c].second - h1 + q.second};
      check_point(blocks[1]->points[c], turned(moved, q, t0 + t1), printed);
    }
  }
  CHECK(peak > 0.005);  // the artefact rocked within the frames checked
}
