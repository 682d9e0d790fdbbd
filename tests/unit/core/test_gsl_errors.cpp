// GSL errors are returned as statuses (never abort()), and needle configs at the edges of the
// schema either run or are refused in one line, with no temporary output left behind.
#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_sf_log.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "granboltz/core/gsl_errors.hpp"
#include "granboltz/tv06/needle.hpp"
#include "test_support.hpp"

namespace granboltz {
namespace {

TEST(GslErrors, AnErrorIsReturnedAndRecordedInsteadOfAborting) {
  install_gsl_error_handler();
  install_gsl_error_handler();  // idempotent
  EXPECT_TRUE(gsl_error_handler_installed());
  clear_gsl_error();
  gsl_sf_result r;
  EXPECT_EQ(gsl_sf_log_e(-1.0, &r), GSL_EDOM);
  EXPECT_EQ(last_gsl_error().gsl_errno, GSL_EDOM);
  EXPECT_GT(std::string(last_gsl_error().file).size(), 0u);
  EXPECT_NE(describe_gsl_status(GSL_EDOM).find("GSL: "), std::string::npos);

  // qag with one subinterval cannot integrate an oscillating function to 1e-12.
  clear_gsl_error();
  gsl_integration_workspace* w = gsl_integration_workspace_alloc(1);
  gsl_function f;
  f.function = [](double x, void*) { return std::sin(100.0 * x) + 2.0; };
  f.params = nullptr;
  double result = 0, error = 0;
  const int status =
      gsl_integration_qag(&f, 0.0, 100.0, 0.0, 1e-12, 1, GSL_INTEG_GAUSS15, w, &result, &error);
  gsl_integration_workspace_free(w);
  EXPECT_NE(status, GSL_SUCCESS);
  EXPECT_EQ(last_gsl_error().gsl_errno, status);
  const std::string message = describe_gsl_status(status);
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(GslErrors, TheInversionSolvesOverManyTurns) {
  // A bracket of ~1e24 half-turns (L = 1e-12): the whole half-turns are counted.
  using namespace tv06;
  const NeedleRate rate(gaussian_bath(1.0, 1.0), 1e-12);
  WaitingTimeSolver solver(rate);
  const NeedleState s{0.3, -0.2, 2e12, 0.4};
  const double t = solver.solve(s, 0.7);
  EXPECT_TRUE(std::isfinite(t));
  const double phi_max = rate.upper_bound(std::hypot(s.vx, s.vy), s.omega);
  const double phi_min = rate.lower_bound(s.omega);
  EXPECT_GE(t, 0.7 / phi_max * (1 - 1e-9));
  EXPECT_LE(t, 0.7 / phi_min * (1 + 1e-9));
  // Moderately many turns, where the direct quadrature still works: the two agree.
  const NeedleRate unit(gaussian_bath(1.0, 1.0), 1.0);
  WaitingTimeSolver a(unit);
  const NeedleState fast{1.0, 0.5, 3e3, 0.1};
  const double target = 20.0;
  const double direct = a.solve(fast, target);
  EXPECT_NEAR(a.integral(fast, direct), target, 1e-8 * target);
}

// The run of `sets` on the tiny needle config: exit 0, 1 or 2, at most 3 lines, no signal, no
// hang, and on a refusal nothing left in the output directory.
void expect_clean(const std::string& sets) {
  test::TempDir dir;
  const std::string out = dir.file("out.h5");
  const std::string cmd = "timeout 60 " + std::string(GRANBOLTZ_BINARY) + " run " +
                          GRANBOLTZ_SOURCE_DIR + "/tests/bad_inputs/base/needle.yaml -q -o " + out +
                          " --threads 2 " + sets + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string text;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, pipe)) text += buf;
  const int status = ::pclose(pipe);
  ASSERT_TRUE(WIFEXITED(status)) << sets;
  const int code = WEXITSTATUS(status);
  EXPECT_TRUE(code == 0 || code == 1 || code == 2) << sets << ": exit " << code << "\n" << text;
  int lines = 0;
  for (char ch : text) lines += ch == '\n';
  EXPECT_LE(lines, 3) << sets << "\n" << text;
  EXPECT_EQ(text.find("gsl:"), std::string::npos) << sets << "\n" << text;
  if (code == 0) {
    EXPECT_EQ(dir.entries(), 1u) << sets;
  } else {
    EXPECT_EQ(dir.entries(), 0u) << sets;
    EXPECT_NE(text.find(" = "), std::string::npos) << sets << ": the key and value\n" << text;
  }
}

TEST(GslErrors, NeedleEdgeValuesRunOrAreRefusedInOneLine) {
  for (const char* value :
       {"needle.length=1e-12", "needle.density=1e-12", "needle.length=1e160",
        "needle.length=1e-200", "needle.mass=5e-324", "needle.mass=1e-300", "needle.mass=1e300",
        "needle.density=1e-320", "needle.density=1e308", "needle.a=1e-300", "needle.a=1e300"})
    for (const char* method : {"inversion", "thinning"})
      expect_clean(std::string("--set ") + value + " --set needle.waiting_time=" + method);
}

TEST(GslErrors, TinyNeedlesRunByInversion) {
  // Many turns per collision: these failed (abort) before; now they run.
  for (const char* value : {"needle.length=1e-12", "needle.density=1e-12"}) {
    test::TempDir dir;
    const auto r = test::run_granboltz(
        "run " + std::string(GRANBOLTZ_SOURCE_DIR) + "/tests/bad_inputs/base/needle.yaml -q -o " +
        dir.file("out.h5") + " --set needle.waiting_time=inversion" + " --set " + value);
    EXPECT_EQ(r.exit_code, 0) << value << ": " << r.output;
  }
}

TEST(GslErrors, NeedleScalesOutsideDoublePrecisionAreRefused) {
  const std::string base =
      "model: needle\nseed: 1\nensembles: 1\nneedle: {mass: 0.5, alpha: 0.5, collisions: 10}\n";
  EXPECT_EQ(test::config_error(base, {"needle.mass=5e-324"}),
            "needle.mass = 5e-324: must be >= 1e-300 (1/M and the speeds overflow)");
  EXPECT_NE(
      test::config_error(base, {"needle.length=1e160"}).find("needle.length = 1e+160: must give"),
      std::string::npos);
  EXPECT_NE(
      test::config_error(base, {"needle.density=1e308"}).find("needle.density = 1e+308: must give"),
      std::string::npos);
  EXPECT_EQ(test::config_error(base, {"needle.length=1e-12"}), "");
}

}  // namespace
}  // namespace granboltz
