// `fmcw evaluate` on a sequence in the AevaScenes layout, as a user runs it: the report's
// figures against the truth the sequence was written from.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "fmcw/io/npz.hpp"
#include "support/aevascenes_writer.hpp"
#include "support/cli.hpp"
#include "support/dataset_files.hpp"
#include "support/temp_dir.hpp"

namespace {

class AevaScenesCli : public fmcw::test::TempDirTest {};

TEST_F(AevaScenesCli, EvaluateRunsOnASequenceAndFindsTheCarAndTheEgo) {
  if (!fmcw::io::npz_supported()) GTEST_SKIP() << "built without libzip";
  const std::filesystem::path seq = dir_ / "00000000-0000-4000-8000-000000000020";
  fmcw::test::write_aevascenes_sequence(seq, 4);
  const fmcw::test::CliResult r =
      fmcw::test::run_cli("evaluate " + seq.string() + " -o " + path("report") + " --no-figures --methods robust,tracked");
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json m = nlohmann::json::parse(fmcw::test::slurp(std::filesystem::path(path("report")) / "metrics.json"));
  EXPECT_EQ(m.at("frames"), 4);
  for (const char* method : {"robust", "tracked"}) {
    SCOPED_TRACE(method);
    const nlohmann::json& x = m.at("methods").at(method);
    EXPECT_GT(x.at("motion").at("accuracy").get<double>(), 0.98) << x.at("motion");
    // The ego at 10 m/s along x, measured after the poses undid the compensation.
    for (const auto& e : x.at("ego_velocity").at("rmse_mps")) EXPECT_LT(e.get<double>(), 0.05) << x.at("ego_velocity");
    // The oncoming car at 5 m/s.
    EXPECT_GE(x.at("objects").at("evaluated").get<int>(), 4);
    EXPECT_LT(x.at("objects").at("median_error_mps").get<double>(), 0.2) << x.at("objects");
  }
}

}  // namespace
