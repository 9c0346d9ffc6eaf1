// `zbrdf preview --turntable / --environment-sequence` end to end through the binary: the frames,
// the animated PNG and animation.json, each frame lit by its own map, the session default, and
// the errors for flags that do not go together.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "acquisition/zonal.h"
#include "basis/png.h"
#include "brdf/dbrdf_file.h"
#include "pictures/image.h"
#include "tests/acquisition/session_fixture.h"
#include "tools_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::TempDir;

uint32_t Be32(const std::string& s, size_t at) {
  return static_cast<uint32_t>(static_cast<uint8_t>(s[at])) << 24 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[at + 1])) << 16 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[at + 2])) << 8 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[at + 3]));
}

TEST(PreviewAnimation, TurntableWritesFramesAnAnimatedPngAndItsRecord) {
  TempDir dir("preview-turntable");
  const std::string out = dir.File("tt"), exr = dir.File("exr");
  ASSERT_EQ(testing::RunZbrdf("preview lambert:0.5 --turntable 4 --size 24 --spp 2 --sampler smc "
                              "--environment studio --out " + out + " --exr " + exr + " --json",
                              dir.File("out.txt"), dir.File("err.txt")),
            0)
      << testing::ReadFile(dir.File("err.txt"));
  for (int t = 0; t < 4; ++t) {
    char name[32];
    std::snprintf(name, sizeof(name), "/frame-%04d", t);
    EXPECT_EQ(DecodePng(testing::ReadFile(out + name + ".png"), name).height, 24) << t;
    EXPECT_EQ(ReadExrImage(exr + name + ".exr").width, 24) << t;
  }
  // The animation: a PNG whose second chunk is acTL with 4 frames.
  const std::string apng = testing::ReadFile(out + "/animation.png");
  ASSERT_GT(apng.size(), 8u + 25 + 20);
  EXPECT_EQ(apng.substr(8 + 25 + 4, 4), "acTL");
  EXPECT_EQ(Be32(apng, 8 + 25 + 8), 4u);
  const nlohmann::json record = nlohmann::json::parse(testing::ReadFile(out + "/animation.json"));
  EXPECT_EQ(record["frames"], 4);
  EXPECT_EQ(record["sampler"], "smc");
  ASSERT_EQ(record["per_frame"].size(), 4u);
  EXPECT_NEAR(record["per_frame"][2]["rotation_deg"].get<double>(), 180.0, 1e-9);
  EXPECT_GT(record["per_frame"][0]["sir_starts"].get<int>(), 0);   // frame 0 starts with SIR
  EXPECT_EQ(record["per_frame"][1]["sir_starts"].get<int>(), 0);   // then carries particles
  EXPECT_GT(record["per_frame"][1]["particles_carried"].get<int>(), 0);
  const nlohmann::json printed = nlohmann::json::parse(testing::ReadFile(dir.File("out.txt")));
  EXPECT_EQ(printed["animation"], out + "/animation.png");
}

TEST(PreviewAnimation, EachFrameOfASequenceIsLitByItsOwnMap) {
  // Three constant maps: a Lambertian ball of albedo 0.5 reflects 0.5 x the map's radiance
  // (the furnace; with 64 particles and 256 candidates the pixel's relative standard error is
  // about 3%, so the mean over the ball's centre 4 x 4 pixels is within 5%).
  TempDir dir("preview-sequence");
  const std::string seq = dir.File("maps");
  std::filesystem::create_directories(seq);
  const double radiance[3] = {1.0, 4.0, 0.25};
  for (int t = 0; t < 3; ++t) {
    RgbImage map(16, 8);
    std::fill(map.pixels.begin(), map.pixels.end(), Rgb(radiance[t]));
    WriteExrImage(seq + "/env-000" + std::to_string(t + 1) + ".exr", map);
  }
  const std::string out = dir.File("out"), exr = dir.File("exr");
  ASSERT_EQ(testing::RunZbrdf("preview lambert:0.5 --environment-sequence " + seq +
                                  " --size 16 --spp 64 --sampler sir --out " + out + " --exr " + exr,
                              dir.File("out.txt"), dir.File("err.txt")),
            0)
      << testing::ReadFile(dir.File("err.txt"));
  for (int t = 0; t < 3; ++t) {
    const RgbImage frame = ReadExrImage(exr + "/frame-000" + std::to_string(t) + ".exr");
    double sum = 0;
    for (int y = 6; y < 10; ++y) {
      for (int x = 6; x < 10; ++x) sum += frame.At(x, y).g / 16;
    }
    EXPECT_NEAR(sum, 0.5 * radiance[t], 0.05 * 0.5 * radiance[t]) << "frame " << t;
  }
  const nlohmann::json record = nlohmann::json::parse(testing::ReadFile(out + "/animation.json"));
  EXPECT_EQ(record["kind"], "environment-sequence");
  EXPECT_EQ(record["per_frame"][2]["environment"], seq + "/env-0003.exr");
}

TEST(PreviewAnimation, ASessionsTurntableGoesIntoTheSessionByDefault) {
  TempDir dir("preview-session-turntable");
  const std::string s = dir.File("session");
  std::filesystem::create_directories(s);
  testing::WriteSessionJson(s, "merl:red-fabric");
  WriteDBrdfFile(s + "/fit-dbrdf.exr", testing::MakeDBrdf(), {{"test", true}});
  ASSERT_EQ(testing::RunZbrdf("preview " + s + " --turntable 2 --size 16 --spp 2",
                              dir.File("out.txt"), dir.File("err.txt")),
            0)
      << testing::ReadFile(dir.File("err.txt"));
  EXPECT_TRUE(std::filesystem::exists(s + "/turntable/animation.png"));
  EXPECT_TRUE(std::filesystem::exists(s + "/turntable/frame-0001.png"));
}

TEST(PreviewAnimation, FlagsThatDoNotGoTogetherAreRefusedByName) {
  TempDir dir("preview-animation-errors");
  auto error_of = [&](const std::string& args) {
    EXPECT_EQ(testing::RunZbrdf("preview lambert:0.5 --size 8 --spp 1 " + args,
                                dir.File("out.txt"), dir.File("err.txt")),
              2)
        << args;
    return testing::ReadFile(dir.File("err.txt"));
  };
  EXPECT_NE(error_of("--turntable 3 --light dir:30,0 --out " + dir.File("a"))
                .find("an animation needs an environment"),
            std::string::npos);
  EXPECT_NE(error_of("--sampler pmc --out " + dir.File("b.png")).find("mis, sir, smc or smc-bridges"),
            std::string::npos);
  EXPECT_NE(error_of("--sampler sir --sampling brdf --out " + dir.File("c.png"))
                .find("--sampling brdf goes with --sampler mis"),
            std::string::npos);
  EXPECT_NE(error_of("--environment-sequence " + dir.File("none") + " --out " + dir.File("d"))
                .find("not a folder"),
            std::string::npos);
  EXPECT_NE(error_of("--turntable 2 --environment-sequence " + dir.path() + " --out " +
                     dir.File("e"))
                .find("exclude each other"),
            std::string::npos);
  EXPECT_NE(error_of("--environment " + dir.File("map.png") + " --out " + dir.File("f.png"))
                .find("unknown file type"),
            std::string::npos);
  EXPECT_NE(error_of("--turntable 2").find("--out is required"), std::string::npos);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
