// The response figure takes its panels from the output schema
// (rocking.quantities) with no list of its own: a quantity whose entry has a
// figure role (excitation, response, loop, joints) is drawn wherever a run's
// history holds its column, so a new quantity declared with a role reaches
// the figure with no change to rocking.plot. Checked by reading the schema's
// three tables (the scalar quantities, each device's, each joint's), never a
// hand list: for every shipped scene, `rocking plot response` of the scene as
// built, and for every history column whose quantity has a figure role, the
// figure's script reads that column by its name (column('NAME [unit]')).
// A loop and the excitation are drawn only when their column is not zero
// throughout (a device that never stretches has no loop), so those are
// required when some row is non-zero. The paper's edge dampers alone (the
// damper_d column and their pair of devices) are drawn as the paper's one
// signed damper loop (Fig. 4), in place of each device's loop and the
// devices' moment (the quantities that need devices).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "csv_table.hpp"
#include "gnuplot_columns.hpp"
#include "run_program.hpp"
#include "temp_path.hpp"
import rocking.quantities;

using namespace rocking;
namespace fs = std::filesystem;

namespace {

bool drawn_role(FigureRole r) { return r != FigureRole::none; }
bool only_when_moving(FigureRole r) { return r == FigureRole::loop || r == FigureRole::excitation; }

// Whether a header column is NAME's: "NAME [unit]", or NAME alone when unitless.
bool is_column_of(const std::string& column, std::string_view name) {
  return column == name || column.starts_with(std::string(name) + " [");
}

bool moves(const CsvTable& t, std::size_t k) {
  return std::ranges::any_of(t.rows, [&](const std::vector<std::string>& row) {
    return k < row.size() && !row[k].empty() && std::strtod(row[k].c_str(), nullptr) != 0.0;
  });
}

}  // namespace

TEST_CASE("the response figure draws every history column whose quantity the schema gives a figure role, on every shipped scene, by name") {
  std::vector<fs::path> scenes;
  for (const fs::directory_entry& e : fs::directory_iterator(ROCKING_SCENES))
    if (e.path().extension() == ".toml") scenes.push_back(e.path());
  std::ranges::sort(scenes);
  REQUIRE(scenes.size() >= 8);
  const fs::path dir = scratch_dir("figure_schema");
  int checked = 0;
  for (const fs::path& scene : scenes) {
    CAPTURE(scene.filename().string());
    const fs::path out = dir / scene.stem();
    const cli::Result r = cli::run("plot response " + scene.string() + " --variants scene --formats png --out " + out.string());
    REQUIRE_MESSAGE(r.code == 0, r.err);
    const std::string script = file_text(out / "response.gp");
    const CsvTable history = csv_table(file_text(out / "response.data" / "scene.csv"));
    CHECK_MESSAGE(numbered_column(script).empty(), numbered_column(script));
    auto require_drawn = [&](std::size_t k, FigureRole role) {
      if (only_when_moving(role) && !moves(history, k)) return;
      CAPTURE(history.header[k]);
      CHECK(script.find("column('" + history.header[k] + "')") != std::string::npos);
      ++checked;
    };
    std::vector<std::string> devices;  // the owners of device columns (NAME.force)
    for (const std::string& column : history.header)
      for (const DeviceQuantityInfo& q : device_quantity_table)
        if (const std::size_t dot = column.find('.'); dot != std::string::npos && !column.starts_with("joint") &&
                                                      is_column_of(column.substr(dot + 1), q.name) &&
                                                      std::ranges::find(devices, column.substr(0, dot)) == devices.end())
          devices.push_back(column.substr(0, dot));
    const bool paper_pair_alone =
        devices.size() == 2 && std::ranges::any_of(history.header, [](const std::string& c) {
          return is_column_of(c, info(Quantity::damper_d).name);
        });
    for (std::size_t k = 0; k < history.header.size(); ++k) {
      const std::string& column = history.header[k];
      for (const QuantityInfo& q : quantity_table)
        if (drawn_role(q.figure.role) && is_column_of(column, q.name) && !(paper_pair_alone && q.needs == Needs::devices))
          require_drawn(k, q.figure.role);
      // A device's quantity: NAME.force; a joint's: jointK.theta (K >= 1).
      const std::size_t dot = column.find('.');
      if (dot == std::string::npos) continue;
      const std::string_view owner(column.data(), dot), rest(column.data() + dot + 1, column.size() - dot - 1);
      const bool joint = owner.starts_with("joint") && owner.size() > 5 &&
                         std::ranges::all_of(owner.substr(5), [](char c) { return c >= '0' && c <= '9'; });
      if (joint) {
        for (const JointQuantityInfo& q : joint_quantity_table)
          if (drawn_role(q.figure.role) && is_column_of(std::string(rest), q.name)) require_drawn(k, q.figure.role);
      } else if (!paper_pair_alone) {
        for (const DeviceQuantityInfo& q : device_quantity_table)
          if (drawn_role(q.figure.role) && is_column_of(std::string(rest), q.name)) require_drawn(k, q.figure.role);
      }
    }
  }
  MESSAGE(checked << " columns with a figure role drawn by name over " << scenes.size() << " scenes");
  CHECK(checked >= 3 * static_cast<int>(scenes.size()));
}
