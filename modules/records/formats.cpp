// The record formats read_record knows, and the detection that picks one
// from a file's content. A new format is a format_NAME.cpp defining its
// FormatReader NAME_format(), declared and listed in `readers` here.
module;
#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>
#include <fmt/format.h>
module rocking.records;
import rocking.errors;

namespace rocking {

// Each reader's definition (format_NAME.cpp), declared where it is registered.
namespace records {
FormatReader geonet_format();
FormatReader knet_format();
FormatReader cosmos_format();
FormatReader at2_format();
FormatReader csv_format();
FormatReader columns_format();
}  // namespace records

namespace {

// In the order detection tries them: the formats with a signature first,
// bare columns last.
const std::vector<records::FormatReader>& readers() {
  static const std::vector<records::FormatReader> all = {
      records::geonet_format(), records::knet_format(), records::cosmos_format(),
      records::at2_format(),    records::csv_format(),  records::columns_format(),
  };
  return all;
}

std::string format_names() {
  std::string out;
  for (const records::FormatReader& r : readers()) out += (out.empty() ? "" : ", ") + r.name;
  return out;
}

}  // namespace

std::vector<RecordFormatInfo> record_formats() {
  std::vector<RecordFormatInfo> out;
  for (const records::FormatReader& r : readers()) out.push_back({r.name, r.description, r.example});
  return out;
}

ExampleRecord example_record() {
  ExampleRecord e;
  for (int i = 0; i < 100; ++i) e.values.push_back(0.3 * std::sin(2 * std::numbers::pi * i / 25.0));
  return e;
}

GroundMotion read_record(const std::string& path, const RecordOptions& o) {
  if (!std::isfinite(o.scale)) throw InputError(fmt::format("--scale must be finite (got {})", o.scale));
  if (o.dt < 0 || !std::isfinite(o.dt)) throw InputError(fmt::format("--dt {}: must be positive", o.dt));
  const records::FormatReader* reader = nullptr;
  if (o.format != "auto") {
    const auto& all = readers();
    const auto it = std::find_if(all.begin(), all.end(), [&](const records::FormatReader& r) { return r.name == o.format; });
    if (it == all.end())
      throw InputError(fmt::format("--format {}: unknown record format (choose auto, {})", o.format, format_names()));
    reader = &*it;
  }
  const std::vector<records::Line> lines = records::read_lines(path);
  const auto first = std::find_if(lines.begin(), lines.end(), [](const records::Line& l) { return !records::blank_or_comment(l); });
  if (first == lines.end()) records::fail(path, 1, "the record is empty");
  if (!reader)
    for (const records::FormatReader& r : readers())
      if (r.detect(path, lines)) {
        reader = &r;
        break;
      }
  if (!reader) {
    std::string look = records::trim(first->text);
    bool text = false;
    for (char& c : look) {
      if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
      text = text || std::isalpha(static_cast<unsigned char>(c));
    }
    records::fail(path, first->number,
                  fmt::format("not a record format this program reads: it starts with {} '{:.50}' (formats: {}; "
                              "--format forces one)",
                              text ? "text" : "numbers", look, format_names()));
  }
  GroundMotion g = reader->read(path, lines, o);
  RecordInfo info = g.info();
  info.format = reader->name;
  const Orientation orientation = component_orientation(info.component);
  if (o.read_as == ReadAs::horizontal && orientation == Orientation::vertical)
    throw InputError(fmt::format("{}: component {} is vertical: give it as the vertical motion (--vertical {}) and "
                                 "choose a horizontal component for the horizontal one",
                                 path, info.component, o.component.empty() ? path : o.component));
  if (o.read_as == ReadAs::vertical && orientation == Orientation::horizontal)
    throw InputError(fmt::format("{}: component {} is horizontal: the vertical motion needs a vertical component",
                                 path, info.component));
  g.set_info(std::move(info));
  if (o.process.any()) g = process(g, o.process);
  if (!o.vertical_component.empty()) {
    RecordOptions up = o;
    up.component = o.vertical_component;
    up.vertical_component.clear();
    up.read_as = ReadAs::vertical;
    up.scale = 1;  // scaled below, with the horizontal motion
    g = g.with_vertical(read_record(path, up));
  }
  if (o.other_horizontal) {
    // The file's first horizontal component, by number, other than this one.
    std::optional<GroundMotion> other;
    for (int k = 1; k <= 3 && !other; ++k) {
      RecordOptions each = o;
      each.component = std::to_string(k);
      each.read_as = ReadAs::any;
      each.vertical_component.clear();
      each.other_horizontal = false;
      each.scale = 1;  // scaled below, with this one
      try {
        GroundMotion c = reader->read(path, lines, each);
        if (c.info().component != g.info().component &&
            component_orientation(c.info().component) == Orientation::horizontal)
          other = o.process.any() ? process(c, o.process) : std::move(c);
      } catch (const InputError&) {
        break;  // no component k: the file has no more
      }
    }
    if (!other)
      throw InputError(fmt::format("{}: holds no other horizontal component beside {} (give the pair's other file)", path,
                                   g.info().component.empty() ? "this one" : g.info().component));
    g = g.with_other_horizontal(*other);
  }
  return o.scale == 1.0 ? g : g.scaled(o.scale);
}

bool is_record_file(const std::string& path) {
  try {
    const std::vector<records::Line> lines = records::read_lines(path);
    for (const records::FormatReader& r : readers())
      if (r.detect(path, lines)) return true;
  } catch (const InputError&) {
  }
  return false;
}

}  // namespace rocking
