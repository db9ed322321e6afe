// Snapshots as labelled maps: the one map table (names, aliases, keys), and every map each
// method publishes has a row in it, a label and a legend that explains it.
#include "methods/snapshot.h"

#include "methods/factory.h"
#include "present/overlays.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

namespace penumbra {
namespace {

TEST(MapTable, NamesAreUniqueAndRoundTrip) {
  std::set<std::string> names;
  std::set<MapId> ids;
  for (const MapInfo& m : mapTable()) {
    EXPECT_NE(m.id, MapId::None);
    EXPECT_TRUE(ids.insert(m.id).second) << m.name << " has a second row";
    ASSERT_NE(m.name, nullptr);
    EXPECT_TRUE(names.insert(m.name).second) << m.name;
    if (m.alias) {
      EXPECT_TRUE(names.insert(m.alias).second) << m.alias;
    }
    ASSERT_NE(m.panelLabel, nullptr);
    EXPECT_GT(std::string(m.panelLabel).size(), 0u);
    EXPECT_EQ(mapByName(m.name), m.id);
    EXPECT_STREQ(mapName(m.id), m.name);
    EXPECT_EQ(findMapInfo(m.id), &m);
  }
  EXPECT_EQ(mapByName("none"), MapId::None);
  EXPECT_STREQ(mapName(MapId::None), "none");
  EXPECT_EQ(findMapInfo(MapId::None), nullptr);
  EXPECT_FALSE(mapByName("sparkle").has_value());
}

TEST(MapTable, OverlaysComeFirstInKeyOrder) {
  int key = 0;
  bool filesOnly = false;
  for (const MapInfo& m : mapTable()) {
    if (m.key == 0) {
      filesOnly = true;
      continue;
    }
    EXPECT_FALSE(filesOnly) << m.name << " has a key after a map without one";
    EXPECT_EQ(m.key, ++key) << m.name;
  }
  EXPECT_EQ(overlayList().size(), size_t(key));
  // The number keys 1-9 reach the first nine; the rest (the film's depth, emission, raw
  // error) are reached by name, from the panel's list or --overlay.
  for (const MapInfo& m : overlayList())
    if (m.key > 9) EXPECT_EQ(overlayByName(m.name), m.id) << m.name;
}

// The names users were promised, and the names of before, all parse as overlays.
TEST(MapTable, OverlayNamesAndAliasesParse) {
  EXPECT_EQ(overlayByName("slices"), MapId::Selected);
  EXPECT_EQ(overlayByName("filter-scale"), MapId::FilterScale);
  const std::pair<const char*, MapId> old[] = {
      {"none", MapId::None},
      {"bias", MapId::ErrorEstimate},
      {"selected", MapId::Selected},
      {"alpha", MapId::FilterScale},
      {"samples", MapId::SampleCount},
      {"traced", MapId::TracedCount},
      {"network_error", MapId::NetworkError},
      {"reference_error", MapId::ReferenceError},
  };
  for (const auto& [name, id] : old) EXPECT_EQ(overlayByName(name), id) << name;
  // Maps without a key are files only: not an overlay, but a map name.
  EXPECT_FALSE(overlayByName("slice_b").has_value());
  EXPECT_EQ(mapByName("slice_b"), MapId::SliceB);
  const std::string names = overlayNames();
  EXPECT_NE(names.find("selected (or slices)"), std::string::npos) << names;
  EXPECT_NE(names.find("alpha (or filter-scale)"), std::string::npos) << names;
}

TEST(Snapshot, AddMapChecksTheSizeAndReplacesAnEqualId) {
  Snapshot s;
  s.width = 2;
  s.height = 2;
  s.addMap(MapId::SampleCount, "kept spp", {1, 2, 3, 4}, MapLegend::sequential(0, 4));
  EXPECT_THROW(s.addMap(MapId::TracedCount, "traced spp", {1, 2, 3}, MapLegend::sequential(0, 4)),
               std::invalid_argument);
  EXPECT_THROW(s.addMap(MapId::None, "nothing", {1, 2, 3, 4}, {}), std::invalid_argument);
  EXPECT_THROW(s.addMap(MapId::Prediction, "I'", {1, 2, 3, 4}, MapLegend::rgb()),
               std::invalid_argument);  // Rgb: three values per pixel
  s.addMap(MapId::Prediction, "I'", std::vector<float>(12, 0.5f), MapLegend::rgb());
  s.addMap(MapId::SampleCount, "kept spp", {5, 6, 7, 8}, MapLegend::sequential(0, 8));
  ASSERT_EQ(s.maps.size(), 2u);
  ASSERT_NE(s.map(MapId::SampleCount), nullptr);
  EXPECT_EQ(s.map(MapId::SampleCount)->values[0], 5.0f);
  EXPECT_EQ(s.map(MapId::TracedCount), nullptr);
}

TEST(Snapshot, PercentileAndFiniteMax) {
  const float nan = std::nanf("");
  EXPECT_EQ(finiteMax(std::vector<float>{1, nan, 3, -5}), 3.0f);
  EXPECT_EQ(finiteMax(std::vector<float>{}), 0.0f);
  EXPECT_EQ(percentileOf(std::vector<float>{}, 0.99f), 1.0f);
  EXPECT_EQ(percentileOf(std::vector<float>{0, 0, 2}, 0.5f), 2.0f);  // 0: the largest value
  EXPECT_EQ(percentileOf(std::vector<float>{1, 2, 3, 4, 5}, 0.5f), 3.0f);
}

// Every map a method publishes has a row in the table, a label, a legend that fits its kind
// and one value per pixel (three for Rgb); no id twice.
void expectMapsExplained(const Snapshot& snap, const std::string& what) {
  std::set<MapId> seen;
  const size_t pixels = size_t(snap.width) * snap.height;
  for (const SnapshotMap& m : snap.maps) {
    const MapInfo* info = findMapInfo(m.id);
    ASSERT_NE(info, nullptr) << what << ": map id " << int(m.id) << " has no name";
    const std::string name = info->name;
    EXPECT_TRUE(seen.insert(m.id).second) << what << ": " << name << " twice";
    EXPECT_NE(m.id, MapId::ReferenceError) << what << ": present/ computes that one";
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
  for (MapId id : {MapId::Selected, MapId::SampleCount, MapId::TracedCount})
    EXPECT_NE(snap.map(id), nullptr) << what << " lacks " << mapName(id);
}

class EveryMethod : public ::testing::TestWithParam<MethodKind> {};

TEST_P(EveryMethod, PublishesOnlyNamedAndExplainedMaps) {
  auto prepared = test::shippedScene("cornell", 12);
  const MethodSpec spec{RunShape::batch(8, 3), defaultConfig(GetParam())};
  auto method = makeMethod(*prepared, spec);
  const std::string name = toString(GetParam());
  method->runRound(nullptr);
  expectMapsExplained(*method->snapshot(false), name + " after the first round, no image");
  method->runRound(nullptr);
  const auto snap = method->snapshot(true);
  expectMapsExplained(*snap, name + " after two rounds");
  EXPECT_EQ(snap->source, SnapshotSource::Method);
  if (GetParam() != MethodKind::Ld) {
    EXPECT_NE(snap->map(MapId::ErrorEstimate), nullptr) << name;
  }
  if (GetParam() == MethodKind::Bp || GetParam() == MethodKind::Gem) {
    EXPECT_NE(snap->map(MapId::FilterScale), nullptr) << name;
  }
  // The inspector's values that stand for a map name one the snapshot has.
  const PixelInspection in = method->inspect(5, 6);
  ASSERT_TRUE(in.valid);
  for (const InspectedValue& v : in.values) {
    EXPECT_FALSE(v.line.empty()) << name << ": " << v.label;
    if (v.map != MapId::None) {
      EXPECT_NE(snap->map(v.map), nullptr) << name << ": " << v.label;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, EveryMethod,
                         ::testing::Values(MethodKind::Ld, MethodKind::Bp, MethodKind::FDiv,
                                           MethodKind::Fuzzy, MethodKind::Gem, MethodKind::Cycles),
                         [](const auto& info) { return std::string(toString(info.param)); });

}  // namespace
}  // namespace penumbra
