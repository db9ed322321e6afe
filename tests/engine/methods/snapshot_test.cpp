// Snapshots as labelled maps: the one map table (names, aliases, keys), and every map each
// method publishes has a row in it, a label and a legend that explains it.
#include "methods/snapshot.h"

#include "methods/bp/state.h"
#include "methods/factory.h"
#include "present/overlays.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

namespace penumbra {
namespace {

// Every map kind the methods publish (and the shared ones) is listed once, with unique names and
// aliases that parse back to it.
TEST(MapKinds, NamesAreUniqueAndRoundTrip) {
  const MethodRegistry& methods = builtinMethods();
  std::set<std::string> names;
  std::set<const MapKind*> kinds;
  for (const MapKind* m : methods.maps()) {
    EXPECT_TRUE(kinds.insert(m).second) << m->name << " is listed twice";
    ASSERT_NE(m->name, nullptr);
    EXPECT_TRUE(names.insert(m->name).second) << m->name;
    if (m->alias) {
      EXPECT_TRUE(names.insert(m->alias).second) << m->alias;
    }
    ASSERT_NE(m->panelLabel, nullptr);
    EXPECT_GT(std::string(m->panelLabel).size(), 0u);
    EXPECT_EQ(methods.mapByName(m->name), MapId(*m));
    EXPECT_STREQ(MapId(*m).name(), m->name);
  }
  for (const MapKind* shared : maps::kShared) EXPECT_TRUE(kinds.count(shared)) << shared->name;
  EXPECT_EQ(methods.mapByName("none"), MapId());
  EXPECT_STREQ(MapId().name(), "none");
  EXPECT_TRUE(MapId().none());
  EXPECT_FALSE(methods.mapByName("sparkle").has_value());
}

TEST(MapKinds, OverlaysComeFirstInKeyOrder) {
  int key = 0;
  bool filesOnly = false;
  const std::vector<const MapKind*> overlays = overlayList();
  for (const MapKind* m : overlays) {
    EXPECT_EQ(m->key, ++key) << m->name;
  }
  for (const MapKind* m : builtinMethods().maps()) {
    if (m->key == 0) {
      filesOnly = true;
      continue;
    }
    EXPECT_FALSE(filesOnly) << m->name << " has a key after a map without one";
  }
  // The reference error is present's own, among the methods' overlays.
  EXPECT_EQ(overlays.size(), size_t(key));
  EXPECT_NE(std::find(overlays.begin(), overlays.end(), &maps::ReferenceError), overlays.end());
  // The number keys 1-9 reach the first nine; the rest (the film's depth, emission, raw
  // error) are reached by name, from the panel's list or --overlay.
  for (const MapKind* m : overlays) {
    if (m->key > 9) {
      EXPECT_EQ(overlayByName(m->name), MapId(*m)) << m->name;
    }
  }
}

// The names users were promised, and the names of before, all parse as overlays.
TEST(MapKinds, OverlayNamesAndAliasesParse) {
  EXPECT_EQ(overlayByName("slices"), MapId(maps::Selected));
  EXPECT_EQ(overlayByName("filter-scale"), MapId(maps::FilterScale));
  const std::pair<const char*, MapId> old[] = {
      {"none", MapId()},
      {"bias", maps::ErrorEstimate},
      {"selected", maps::Selected},
      {"alpha", maps::FilterScale},
      {"samples", maps::SampleCount},
      {"traced", maps::TracedCount},
      {"network_error", maps::NetworkError},
      {"reference_error", maps::ReferenceError},
  };
  for (const auto& [name, id] : old) EXPECT_EQ(overlayByName(name), id) << name;
  // Maps without a key are files only: not an overlay, but a map name.
  EXPECT_FALSE(overlayByName("slice_b").has_value());
  EXPECT_EQ(builtinMethods().mapByName("slice_b"), MapId(maps::SliceB));
  const std::string names = overlayNames();
  EXPECT_NE(names.find("selected (or slices)"), std::string::npos) << names;
  EXPECT_NE(names.find("alpha (or filter-scale)"), std::string::npos) << names;
}

TEST(Snapshot, AddMapChecksTheSizeAndReplacesAnEqualId) {
  Snapshot s;
  s.width = 2;
  s.height = 2;
  s.addMap(maps::SampleCount, "kept spp", {1, 2, 3, 4}, MapLegend::sequential(0, 4));
  EXPECT_THROW(s.addMap(maps::TracedCount, "traced spp", {1, 2, 3}, MapLegend::sequential(0, 4)),
               std::invalid_argument);
  EXPECT_THROW(s.addMap(MapId(), "nothing", {1, 2, 3, 4}, {}), std::invalid_argument);
  EXPECT_THROW(s.addMap(maps::Prediction, "I'", {1, 2, 3, 4}, MapLegend::rgb()),
               std::invalid_argument);  // Rgb: three values per pixel
  s.addMap(maps::Prediction, "I'", std::vector<float>(12, 0.5f), MapLegend::rgb());
  s.addMap(maps::SampleCount, "kept spp", {5, 6, 7, 8}, MapLegend::sequential(0, 8));
  ASSERT_EQ(s.maps.size(), 2u);
  ASSERT_NE(s.map(maps::SampleCount), nullptr);
  EXPECT_EQ(s.map(maps::SampleCount)->values[0], 5.0f);
  EXPECT_EQ(s.map(maps::TracedCount), nullptr);
}

TEST(Snapshot, PercentileAndFiniteMax) {
  const float nan = std::nanf("");
  EXPECT_EQ(finiteMax(std::vector<float>{1, nan, 3, -5}), 3.0f);
  EXPECT_EQ(finiteMax(std::vector<float>{}), 0.0f);
  EXPECT_EQ(percentileOf(std::vector<float>{}, 0.99f), 1.0f);
  EXPECT_EQ(percentileOf(std::vector<float>{0, 0, 2}, 0.5f), 2.0f);  // 0: the largest value
  EXPECT_EQ(percentileOf(std::vector<float>{1, 2, 3, 4, 5}, 0.5f), 3.0f);
}

// Every map a method publishes is one of the kinds its descriptor lists, with a label, a legend
// that fits its kind and one value per pixel (three for Rgb); no id twice. A map of slice
// indices says how many slices a pixel side has.
void expectMapsExplained(const Snapshot& snap, const MethodDescriptor& method,
                         const std::string& what) {
  std::set<const MapKind*> seen;
  const size_t pixels = size_t(snap.width) * snap.height;
  for (const SnapshotMap& m : snap.maps) {
    ASSERT_FALSE(m.id.none()) << what;
    const std::string name = m.id.name();
    const auto& listed = method.maps();
    EXPECT_NE(std::find(listed.begin(), listed.end(), m.id.kind()), listed.end())
        << what << ": " << name << " is not among its descriptor's maps";
    EXPECT_TRUE(seen.insert(m.id.kind()).second) << what << ": " << name << " twice";
    EXPECT_NE(m.id, maps::ReferenceError) << what << ": present/ computes that one";
    if (m.id.kind()->slices != SliceRole::None) {
      EXPECT_GT(m.slicesPerSide, 0) << what << ": " << name;
    }
    EXPECT_FALSE(m.label.empty()) << what << ": " << name << " has no label";
    EXPECT_EQ(m.values.size(), pixels * m.channels()) << what << ": " << name;
    switch (m.legend.kind) {
      case ColorMapKind::Sequential:
      case ColorMapKind::Diverging:
        EXPECT_TRUE(std::isfinite(m.legend.minValue) && std::isfinite(m.legend.maxValue))
            << what << ": " << name;
        EXPECT_GT(m.legend.maxValue, m.legend.minValue) << what << ": " << name;
        break;
      case ColorMapKind::Categorical:
        EXPECT_FALSE(m.legend.categories.empty()) << what << ": " << name << " has no categories";
        for (float v : m.values) {
          if (v >= 0) {
            EXPECT_LT(size_t(v), m.legend.categories.size()) << what << ": " << name;
          }
        }
        break;
      case ColorMapKind::Rgb:
        EXPECT_EQ(m.channels(), 3u);
        break;
    }
  }
  // The maps every method has.
  for (MapId id : {MapId(maps::Selected), MapId(maps::SampleCount), MapId(maps::TracedCount)})
    EXPECT_NE(snap.map(id), nullptr) << what << " lacks " << id.name();
}

class EveryMethod : public ::testing::TestWithParam<const MethodDescriptor*> {};

TEST_P(EveryMethod, PublishesOnlyNamedAndExplainedMaps) {
  auto prepared = test::shippedScene("cornell", 12);
  const MethodDescriptor& descriptor = *GetParam();
  const MethodSpec spec{RunShape::batch(8, 3), descriptor.defaults()};
  auto method = makeMethod(*prepared, spec);
  const std::string name = descriptor.title();
  method->runRound(nullptr);
  expectMapsExplained(*method->snapshot(false), descriptor,
                      name + " after the first round, no image");
  method->runRound(nullptr);
  const auto snap = method->snapshot(true);
  expectMapsExplained(*snap, descriptor, name + " after two rounds");
  EXPECT_EQ(snap->source, SnapshotSource::Method);
  const MethodAbilities can = descriptor.abilities(spec.config);
  if (can.adapts) {
    EXPECT_NE(snap->map(maps::ErrorEstimate), nullptr) << name;
  }
  if (can.filters) {
    EXPECT_NE(snap->map(maps::FilterScale), nullptr) << name;
  }
  // The inspector's values that stand for a map name one the snapshot has.
  const PixelInspection in = method->inspect(5, 6);
  ASSERT_TRUE(in.valid);
  for (const InspectedValue& v : in.values) {
    EXPECT_FALSE(v.line.empty()) << name << ": " << v.label;
    if (!v.map.none()) {
      EXPECT_NE(snap->map(v.map), nullptr) << name << ": " << v.label;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, EveryMethod, ::testing::ValuesIn(builtinMethods().methods()),
                         [](const auto& info) {
                           std::string name = info.param->name() + info.param->algorithm();
                           std::erase(name, '-');
                           return name;
                         });

}  // namespace
}  // namespace penumbra
