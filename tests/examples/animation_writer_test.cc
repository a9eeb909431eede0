// AnimationRecorder: URDF visuals reach the page (box sizes in three.js axes: URDF (x, y, z) = three.js (x, z, y)),
// frames are decimated to the frame rate, and a link without visuals gets capsules.
#include "systems/visualization/animation.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include "tests/common/source_path.h"

namespace rome::visualization {
namespace {

TEST(AnimationRecorder, VisualsAndDecimation) {
  const MultibodyModel model = MultibodyModel::Load(rome::test::SourcePath("tests/examples/data_visual_slider.urdf"),
                                                    "", {.euler_floating_base = true});
  AnimationRecorder rec(model, 60.0);
  for (int k = 0; k <= 1000; ++k)
    rec.Record(k * 1e-3, Eigen::VectorXd::Constant(1, 0.001 * k), "free", Eigen::VectorXd::Zero(0));
  // Samples every 1 ms, a frame at least 1/60 s after the previous: frames 17 ms apart, 0 ... 986 ms.
  EXPECT_EQ(rec.num_frames(), 1000 / 17 + 1);
  const std::string path = rome::test::ScratchDir() + "/visual_slider.html";
  std::string error;
  ASSERT_TRUE(rec.WriteHtml(path, "visuals", {}, &error)) << error;
  std::stringstream page;
  page << std::ifstream(path).rdbuf();
  const std::string html = page.str();
  EXPECT_NE(html.find("\"type\":\"box\",\"size\":[0.3,0.1,0.2]"), std::string::npos);
  EXPECT_NE(html.find("\"type\":\"cylinder\",\"size\":[0.05,0.4]"), std::string::npos);
  EXPECT_NE(html.find("\"type\":\"sphere\",\"size\":[0.07]"), std::string::npos);
  EXPECT_EQ(html.find("@DATA@"), std::string::npos);
  EXPECT_LT(html.size(), 5u << 20);
}

TEST(AnimationRecorder, UnwritablePathIsNamed) {
  std::string error;
  EXPECT_FALSE(AnimationRecorder::CheckWritable("/proc/no/such/page.html", &error));
  EXPECT_EQ(error, "animation /proc/no/such/page.html: the folder /proc/no/such does not exist");
}

}  // namespace
}  // namespace rome::visualization
