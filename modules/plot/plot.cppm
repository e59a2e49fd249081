// rocking.plot: figures rendered headlessly by gnuplot 5.4 (pngcairo, pdfcairo,
// svg; TOOLCHAIN.md, plotting). It knows no physics: it is given data files
// and series descriptions, writes a gnuplot script beside them, and runs
// gnuplot in that folder. The script renders every requested format in one
// loop, so a user can restyle a figure and re-render it with `gnuplot NAME.gp`
// without running any simulation again.
// The response figure (the paper's Fig. 4 style) reads the history CSV that
// `rocking simulate` writes, finding each column by its name in the header
// (the names of rocking.quantities), never by its position.
// Keys never cover data: figures whose panels share their series carry one
// key above the panels; figures whose panels differ carry theirs below each.
module;
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>
export module rocking.plot;

export namespace rocking::plot {

struct Figure {
  std::filesystem::path dir;   // where the figure, its script and data go
  std::string name;            // file stem: NAME.png, NAME.pdf, NAME.svg, NAME.gp (a name, not a path)
  std::string title;
  std::vector<std::string> formats{"png", "pdf", "svg"};
  int width = 1000, height = 1300;  // pixels (PNG, SVG); PDF at 100 px per inch
  std::string time_range = {};      // non-empty: the time axes' gnuplot range, e.g. "[45:80]" (response figure)
};

// InputError naming `option` unless `name` is a file stem that stays in its
// folder: not empty, no '/', no control character, not "." or "..".
void check_name(const std::string& name, const std::string& option);

// "png,pdf" -> {"png", "pdf"}; InputError for anything else.
std::vector<std::string> parse_formats(const std::string& list);

// How a run of the response figure ended, when its curves stop at a state
// the figure marks: `separated` (MODEL.md 15, 16: a joint in tension, the
// part above would leave it; on rocking columns, a column top in tension).
// An overturned run needs none: its rocking angle reaches the slenderness.
struct RunEnd {
  bool separated = false;
  std::optional<int> joint;  // the joint in tension (0 the base, K >= 1 joint K); none: the columns' tops
};

// One run of the response figure: its legend, its history CSV (a path
// relative to the figure's folder, or absolute) and how it ended.
struct ResponseSeries {
  std::string label;
  std::string history;
  RunEnd end = {};
};

// What a history file holds: InputError unless it has the header (t first)
// and at least two rows. columns: each column's name (its header field
// without the unit) and 1-based number, headers: each header field as
// written ("delta_t [-]"), nonzero: whether some row of each column is not
// zero; rocks / elastic / has_damper: some row has theta / delta_e / damper_d
// other than zero; ground: it has the a_g column, and ground_moves: some a_g
// is not zero; devices: the names of the devices with NAME.elongation and
// NAME.force columns; joints: the highest K of its jointK.NAME columns (0:
// none).
struct HistoryContent {
  bool rocks = false, elastic = false, has_damper = false, ground = false, ground_moves = false;
  std::vector<std::string> devices;
  int joints = 0;
  int rows = 0;  // data rows under the header
  std::vector<std::pair<std::string, int>> columns;
  std::vector<std::string> headers;
  std::vector<bool> nonzero;
  int column(std::string_view name) const;          // its number; 0 when absent
  std::string header(std::string_view name) const;  // its header field; empty when absent
  bool moves(std::string_view name) const;          // the column is there and not zero throughout
};
HistoryContent check_history(const std::filesystem::path& file);

// Writes NAME.gp and renders it; returns the figure files written. The
// panels are those of the output schema (rocking.quantities' FigureUse), in
// the order of their ranks, each drawn when some run's history has its
// column: the ground acceleration, the drifts, the rocking angle, the
// joints' rotations (one curve per joint in its run's colour and dash, the
// joints told apart by markers named in the axis label when there are
// several), a separated run's end marked on the curve of the joint that
// separates, with a key entry in words ("joint 1 separates"),
// and the hysteresis of the devices: the paper's edge dampers alone as one
// loop signed by the pivot; any other device (a tendon, a viscous damper)
// draws each device's force against its elongation, and the devices' moment
// against theta (a tendon with dampers: the flag-shaped loop of controlled
// rocking). Every column is read by its header name.
std::vector<std::filesystem::path> render_response(const Figure& fig, const std::vector<ResponseSeries>& runs);

// Mode shapes: a data file of whitespace-separated columns under a header
// row naming them, one row per node (the column "height", then one column per
// shape), and one legend per shape column; two panels side by side.
struct ModePanel {
  std::string title;
  std::vector<std::string> labels;  // one per shape column
  std::vector<int> colours;         // palette index per shape column (the same mode, the same colour)
  std::vector<std::string> columns = {};  // one per shape column: its name in the data file's header
};
std::vector<std::filesystem::path> render_modes(const Figure& fig, const std::string& data_file,
                                                const ModePanel& left, const ModePanel& right);

// A grid of panels sharing the x axis quantity, one line per series: for IDA
// curves and parametric studies. Each series is a CSV file whose header row
// names its columns; each panel says what it plots as gnuplot expressions of
// columns by name (column("delta_t") + "*100").
// A vertical line across a panel at x, labelled at its top (a period).
struct Mark {
  double x;
  std::string label;
};
struct Panel {
  std::string ylabel;
  std::string x, y;
  bool from_zero = false;   // the y axis starts at zero (peaks of magnitudes)
  std::string point_label;  // non-empty: a text at every point (e.g. "sprintf('%.0e', column('rtol'))")
  std::vector<Mark> marks = {};
  std::string xrange = {};  // non-empty: the x axis's range, e.g. "[6:170]" (else autoscaled)
  bool log_y = false;       // a logarithmic y axis (from_zero ignored; values <= 0 not drawn)
  std::string xtics = {};   // non-empty: the x axis's tics, e.g. "(8, 16, 32)" (else gnuplot's)
};
// Where a point of an IDA curve stands against overturning: a survivor
// below the first overturning (joined by the line), the first overturning (a
// large cross, the line ends before it), a later one (a small cross), a
// survivor above an overturning (an open point, not joined). Figure data
// hold it as its number.
enum class Collapse : unsigned { standing = 0, first = 1, again = 2, standing_again = 3 };
// A point's Collapse: whether its run overturned, and whether a run at a
// lower level of the same curve did (`fallen`).
constexpr Collapse collapse_of(bool overturned, bool fallen) {
  return overturned ? (fallen ? Collapse::again : Collapse::first)
                    : (fallen ? Collapse::standing_again : Collapse::standing);
}
constexpr unsigned collapse_bit(Collapse c) { return 1u << static_cast<unsigned>(c); }
struct Series {
  std::string label;
  std::string file;  // relative to the figure's folder, or absolute
  // Panels (indices) whose quantity this series does not have (a fixed base's
  // rocking angle): nothing is drawn there, no zero line, no key entry.
  std::vector<std::size_t> absent;
  // Non-empty: the column (its header name) holding each point's Collapse
  // as its number, drawn as IDA curves draw it.
  std::string collapse_column = {};
  // The collapses other than standing that occur (bit k for Collapse k:
  // collapse_bit): the key explains those.
  unsigned collapse_codes = 0;
  // Added to x at this series' collapse markers, so that the markers of
  // series that collapse at the same point stand side by side (data units).
  double dodge = 0;
  bool points = true;  // false: a line only (time histories, spectra)
};
// loglog: both axes logarithmic (work-precision diagrams).
std::vector<std::filesystem::path> render_panels(const Figure& fig, int rows, int cols, const std::string& xlabel,
                                                 const std::vector<Panel>& panels, const std::vector<Series>& series,
                                                 bool loglog = false);

// Panels of lines from files, each line styled by its role: for IDA curves
// over a suite (every record thin and grey, fractiles bold, collapses
// crossed) and fragility curves with their data points. A file is CSV with a
// header row, x in column 1 and y in column 2; a blank line breaks a line (one
// file can hold many curves). One key above the panels lists each label once.
// A band is a translucent area between columns 2 and 3 (an interval around
// a curve). A line with no file is a key entry only: with many series, the
// key can name colours (one entry per colour) and styles (one per style, in
// dark grey: colour -1) apart instead of every pair.
struct Line {
  enum class Style { thin_grey, bold, bold_dashed, circles, squares, crosses, band } style = Style::bold;
  std::string label;  // empty: no key entry
  std::string file;   // relative to the figure's folder, or absolute; empty: a key entry only
  int colour = 0;     // palette index (not for thin_grey); -1: dark grey
  int dash = 0;       // bold: gnuplot dash type - 1 (0 solid), to tell curves apart in greyscale
  int marker = 0;     // bold, bold_dashed: > 0, a gnuplot point type drawn at a few points along the line
  // The file's columns drawn, by header name: x and y (a band: x, low, high).
  std::vector<std::string> columns = {};
};
struct LinePanel {
  std::string title;
  std::vector<Line> lines;      // none: the panel says it has nothing to show
  std::string yrange = "0:*";   // gnuplot range
  std::string xrange = "0:*";
};
std::vector<std::filesystem::path> render_lines(const Figure& fig, int rows, int cols, const std::string& xlabel,
                                                const std::string& ylabel, const std::vector<LinePanel>& panels);

// A law fitted to a cyclic test (the paper's Fig. 2, top right): the data
// file has, by header name, the column `time_column` (the sample time or
// number), "e [m]" (elongation), "F measured [N]" and "F fitted [N]". Left:
// measured (grey points) and fitted loops, force against elongation; right:
// the residual (fitted - measured) against time.
std::vector<std::filesystem::path> render_fit(const Figure& fig, const std::string& data_file,
                                              const std::string& fitted_label, const std::string& time_label,
                                              const std::string& time_column);
// Overturning spectra: each series file has, by header name, the columns
// frequency_ratio, amplitude_ratio, period_s, amplitude_g, overturned (0/1),
// and the cell of each grid point: frequency_ratio_low/_high,
// amplitude_ratio_low/_high, period_low_s/period_high_s and
// amplitude_low_g/amplitude_high_g. The cells where the block overturns are
// filled, one translucent colour per series, normalised axes on the left,
// seconds and g on the right.
std::vector<std::filesystem::path> render_spectrum(const Figure& fig, const std::vector<Series>& series,
                                                   const std::string& normalised_x, const std::string& normalised_y);

// Text from anywhere (a record's header, a file or scene name) as a gnuplot
// string expression that gnuplot never interprets: single-quoted literals
// (single quotes stop backquote substitution and escapes; a ' is doubled),
// joined by "\n" where the text has a newline; other control characters
// become spaces. Every text a script holds goes through it.
std::string quote(std::string_view text);

// Text for a gnuplot comment: one line, control characters as spaces.
std::string comment(std::string_view text);

// A data file's column by its header name, for a `using` clause of a script
// that reads its data with `set datafile columnheaders`: "column('delta_t')".
// Only names the program makes (the schema's, a file's own header words:
// letters, digits, _ . - / space and the brackets of a unit, "t [s]") are
// accepted, never text from input (a device's name): InputError otherwise.
std::string column(std::string_view name);

// Runs a program (argv[0] an absolute path, no shell) in `dir` with its
// standard output and error going to `log` and standard input from
// /dev/null; returns its exit status (-1 when it could not start or was
// killed by a signal).
int run_program(const std::filesystem::path& dir, const std::vector<std::string>& argv,
                const std::filesystem::path& log);
// A check that run_program polls while its program runs (the program's stop
// request: Ctrl-C, SIGTERM); once it returns true the program is ended with
// SIGTERM, run_program returns -1 and render_script throws RunError, leaving
// no figure file it was writing. None (the default): programs run to the end.
void set_interrupt(bool (*requested)());

// Writes DIR/NAME.gp and runs gnuplot on it in DIR; returns the files
// NAME.<format> it made, one per fig.formats entry (RunError if any is missing).
// For scripts that set their own terminal (animations).
std::vector<std::filesystem::path> render_script(const Figure& fig, const std::string& script);

// "WIDTHxHEIGHT" in pixels, at least min_width x min_height and at most max_side
// each; InputError naming --size otherwise.
std::pair<int, int> parse_size(const std::string& text, int min_width, int min_height, int max_side);

// A program on PATH, or empty.
std::string find_program(const std::string& name);

// The gnuplot program: $ROCKING_GNUPLOT, else `gnuplot` on PATH. RunError
// with what to install when there is none.
std::string find_gnuplot();

}  // namespace rocking::plot
