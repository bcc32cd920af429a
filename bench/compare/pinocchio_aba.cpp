// Pinocchio's articulated-body algorithm (ABA) on the benchmark systems, timed in C++ so that
// no Python call overhead is counted against it. Built and run by bench/compare/run.sh.
//   pinocchio_aba nlink N     planar N-link pendulum, point masses m = 1 on rods l = 1
//   pinocchio_aba chain3d N   3-D chain of N rods on universal joints (rotation about x, then y)
//   pinocchio_aba KIND N REPS  REPS evaluations per sample (default 20000), 15 samples: two
//                              runs under callgrind with different REPS give the instructions
//                              of one evaluation (bench/compare/callgrind.sh)
// Prints the median time of one forward-dynamics evaluation in nanoseconds.
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using pinocchio::Inertia;
using pinocchio::SE3;

static pinocchio::Model nlink(int n) {
  pinocchio::Model model;
  pinocchio::JointIndex parent = 0;
  for (int i = 0; i < n; ++i) {
    SE3 placement = SE3::Identity();
    if (i > 0) placement.translation() << 0, -1.0, 0;
    parent = model.addJoint(parent, pinocchio::JointModelRZ(), placement, "j" + std::to_string(i));
    model.appendBodyToJoint(parent, Inertia(1.0, Eigen::Vector3d(0, -1.0, 0), Eigen::Matrix3d::Zero()));
  }
  model.gravity.linear() << 0, -9.81, 0;
  return model;
}

static pinocchio::Model chain3d(int n) {
  const double m = 1.0, l = 1.0, j = 0.001;
  pinocchio::Model model;
  pinocchio::JointIndex parent = 0;
  for (int i = 0; i < n; ++i) {
    SE3 placement = SE3::Identity();
    if (i > 0) placement.translation() << 0, 0, -l;
    // Universal joint: about x, then about the turned y; the intermediate body is massless.
    auto jx = model.addJoint(parent, pinocchio::JointModelRX(), placement, "ax" + std::to_string(i));
    parent = model.addJoint(jx, pinocchio::JointModelRY(), SE3::Identity(), "by" + std::to_string(i));
    Eigen::Matrix3d inertia = Eigen::Vector3d(m * l * l / 12, m * l * l / 12, j).asDiagonal();
    model.appendBodyToJoint(parent, Inertia(m, Eigen::Vector3d(0, 0, -l / 2), inertia));
  }
  model.gravity.linear() << 0, 0, -9.81;
  return model;
}

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: pinocchio_aba nlink|chain3d N [REPS]\n");
    return 2;
  }
  const int n = std::atoi(argv[2]);
  pinocchio::Model model = std::strcmp(argv[1], "chain3d") == 0 ? chain3d(n) : nlink(n);
  pinocchio::Data data(model);
  Eigen::VectorXd q = Eigen::VectorXd::Constant(model.nq, 0.3);
  Eigen::VectorXd v = Eigen::VectorXd::Constant(model.nv, 0.1);
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(model.nv);
  const int reps = argc > 3 ? std::max(1, std::atoi(argv[3])) : 20000;
  std::vector<double> samples;
  double sink = 0;
  for (int s = 0; s < 15; ++s) {
    auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) {
      q[0] += 1e-12;
      pinocchio::aba(model, data, q, v, tau);
      sink += data.ddq[0];
    }
    auto t1 = std::chrono::steady_clock::now();
    samples.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / reps);
  }
  std::sort(samples.begin(), samples.end());
  std::printf("%.1f\n", samples[samples.size() / 2]);
  return sink == 12345.678 ? 1 : 0;
}
