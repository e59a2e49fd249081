// What rocking at joints and on columns costs against the structures they
// extend (issues 54 and 55), under El Centro N-S at the default tolerance:
// each pair's two runs alternate, best of N each, so that their ratio is
// measured in one run on the same machine state. The targets (issue 55): the
// rigid frame costs about the rigid block; the chimney on columns at most
// twice the chimney; (issue 54) the two stacked blocks at most three times
// the rigid block, the cracked chimney at most three times the chimney. The
// cracked chimney's top leaves its joint at 0.21 x El Centro (its run ends
// there, `separated`): the pair runs both at 0.2 x, where both run the whole
// record, so that the ratio is what the chain's equations cost against the
// one-body ones over the same motion. The chimney on columns' fixed-base
// twin, stepped exactly with no right-hand side, is reported for information,
// as is the cracked chimney at 0.05 x, where neither structure lifts: both
// are stepped exactly in full contact, so that the ratio is the cost of the
// chain's closed phase (its guards, reactions and outputs) alone.
// Usage: structures_bench [RECORDS_DIR] [--repeats N] [--only TEXT]
//   RECORDS_DIR: default ../shared/data/records or $ROCKING_RECORDS.
//   --only TEXT: the pairs whose first label contains TEXT (for profiling one).
#include <fmt/format.h>
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>
import rocking;

using namespace rocking;

namespace {

struct Case {
  std::string label, scene;
  std::vector<std::string> overrides;
  double scale = 1;  // on the record
};

struct Timed {
  double best_s = 1e9;
  RunResult last;
};

PreparedRun prepared(const Case& c, const std::string& record) {
  RunSpec spec{.scene = load_scene(std::string(ROCKING_SOURCE_DIR) + "/data/scenes/" + c.scene, c.overrides)};
  spec.motion.record = record;
  spec.motion.scale = c.scale;
  return prepare_run(spec);
}

std::string only;  // --only: the pairs whose first label contains it

void pair(const Case& a, const Case& b, const std::string& record, int repeats, double target) {
  if (a.label.find(only) == std::string::npos) return;
  const PreparedRun pa = prepared(a, record), pb = prepared(b, record);
  Timed ta, tb;
  for (int i = 0; i < repeats; ++i)
    for (auto [p, t] : {std::pair{&pa, &ta}, std::pair{&pb, &tb}}) {
      t->last = simulate(p->model, p->motion, p->options);
      t->best_s = std::min(t->best_s, t->last.wall_s);
    }
  for (const auto& [c, t] : {std::pair{&a, &ta}, std::pair{&b, &tb}})
    fmt::print("  {:<44} {:9.3f} ms  {:>8} rhs  {:>4} impacts  {}\n", c->label, 1e3 * t->best_s, t->last.stats.rhs,
               t->last.counts.impacts, outcome_name(t->last.outcome));
  const double ratio = ta.best_s / tb.best_s;
  if (target > 0)
    fmt::print("  ratio {:.2f} (target at most {:.1f}): {}\n\n", ratio, target, ratio <= target ? "met" : "MISSED");
  else
    fmt::print("  ratio {:.2f}\n\n", ratio);
}

}  // namespace

int main(int argc, char** argv) {
  std::string records = std::getenv("ROCKING_RECORDS") ? std::getenv("ROCKING_RECORDS") : "../shared/data/records";
  int repeats = 20;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--repeats") == 0 && i + 1 < argc) repeats = std::max(1, std::atoi(argv[++i]));
    else if (std::strcmp(argv[i], "--only") == 0 && i + 1 < argc) only = argv[++i];
    else records = argv[i];
  }
  const std::string elcentro = records + "/elcentro_1940_ns.at2";
  try {
    fmt::print("El Centro N-S ({}), default tolerance, best of {} alternating runs each\n\n", elcentro, repeats);
    pair({"rigid frame (rocking_frame.toml)", "rocking_frame.toml", {}},
         {"rigid block (rigid_block.toml)", "rigid_block.toml", {}}, elcentro, repeats, 1.5);
    pair({"chimney on columns (chimney_on_columns.toml)", "chimney_on_columns.toml", {}},
         {"chimney (christchurch_chimney.toml)", "christchurch_chimney.toml", {}}, elcentro, repeats, 2.0);
    pair({"chimney on columns", "chimney_on_columns.toml", {}},
         {"its fixed-base twin (no dampers)", "christchurch_chimney.toml", {"contact.rocking=false", "damper.enabled=false"}},
         elcentro, repeats, 0);
    pair({"stacked blocks (stacked_blocks.toml)", "stacked_blocks.toml", {}},
         {"rigid block (rigid_block.toml)", "rigid_block.toml", {}}, elcentro, repeats, 3.0);
    pair({"cracked chimney, 0.2 x (chimney_cracked.toml)", "chimney_cracked.toml", {}, 0.2},
         {"chimney, 0.2 x (christchurch_chimney.toml)", "christchurch_chimney.toml", {}, 0.2}, elcentro, repeats, 3.0);
    pair({"cracked chimney, 0.05 x (no joint lifts)", "chimney_cracked.toml", {}, 0.05},
         {"chimney, 0.05 x", "christchurch_chimney.toml", {}, 0.05}, elcentro, repeats, 0);
  } catch (const std::exception& e) {
    fmt::print(stderr, "structures_bench: {}\n", e.what());
    return 1;
  }
  return 0;
}
