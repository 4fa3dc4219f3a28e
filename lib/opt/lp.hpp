#pragma once
// The minimax problem for a fixed target point is a linear programme (GLPK):
//
//     minimise t   over z, t
//     subject to   off_rows z - t <= 0         every off-target sample stays below t
//                  target_row . z  = 1         the target point's AF is 1
//                  -c <= (B z)_i <= c           optional: bound each weight (efficiency)
//                  capped_rows z <= caps       optional: samples held below a fixed value
//                                              (a focus: the target's own AF away from it)
//
// Its value is the best ratio achievable when the target fires at that point.  Solving it
// for many target points reuses one GLPK problem and warm-starts from the last basis.
// Constraint generation: the LP holds only some of the off-target samples (an even spread,
// then the most violated ones, added until no sample is violated); with thousands of
// samples and a few dozen active ones this is much faster than all rows at once, and the
// answer is the same (a solution of a relaxation that violates nothing is optimal).

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Dense>

struct glp_prob;

namespace tp {

// Room for need entries in v, with an eighth to spare when it must grow: rows appended a
// few at a time (a focus's rounds) then fit without moving the whole table each time.
inline void reserve_spare(std::vector<double>& v, std::size_t need) {
  if (v.capacity() < need) v.reserve(need + need / 8);
}

struct LpSolution {
  double value = 0.0;  // t: the largest off-target AF when the target point's AF is 1
  Eigen::VectorXd z;
};

// Frees this thread's GLPK environment (GLPK keeps one per thread): for a thread about to
// end, every TargetLp it made destroyed.
void release_lp_thread();

// Makes GLPK fail on purpose (an invalid argument), to test that its failures become a
// tp::Error instead of abort(), with nothing printed.  Throws tp::Error (failure).
void provoke_glpk_error();

class TargetLp {
 public:
  // basis and weight_bound: when weight_bound > 0, |(basis z)_i| <= weight_bound.
  // off_rows is kept (scaled; move it in when the caller is done with it).  capped_rows
  // (with as many columns) and caps: rows held at or below a value each.
  TargetLp(Eigen::MatrixXd off_rows, const Eigen::MatrixXd& basis, double weight_bound,
           const Eigen::MatrixXd& capped_rows = Eigen::MatrixXd(),
           const Eigen::VectorXd& caps = Eigen::VectorXd());
  ~TargetLp();
  TargetLp(const TargetLp&) = delete;
  TargetLp& operator=(const TargetLp&) = delete;

  // More samples, kept like the first (scaled by the first rows' scale).  They enter the
  // LP when a solve finds them violated, and the rows already in it stay: the next solve
  // starts from the last basis (a focus's rounds add samples to one problem).
  void append(const Eigen::MatrixXd& off_rows, const Eigen::MatrixXd& capped_rows,
              const Eigen::VectorXd& caps);
  // New bounds for every capped row, in the order the rows were given.
  void set_caps(const Eigen::VectorXd& caps);

  // No value when infeasible or unbounded.  A GLPK failure (which GLPK itself would end
  // with abort()) is a tp::Error (failure), and its output never reaches stdout.
  std::optional<LpSolution> solve(const Eigen::VectorXd& target_row);

 private:
  void add(const std::vector<Eigen::Index>& rows);  // samples into the LP
  void keep(const Eigen::MatrixXd& rows, const Eigen::VectorXd* caps);

  glp_prob* lp_ = nullptr;
  // Every sample's row, scaled, row-major (rows x nz_), in the order given.
  std::vector<double> rows_;
  std::vector<Eigen::Index> cap_of_;  // per row: its index in caps_, or -1 (off-target: <= t)
  std::vector<double> caps_;          // the capped rows' bounds, in the order given
  std::vector<int> glp_row_;          // per row: its row in the LP, or 0
  std::size_t rows_in_lp_ = 0;
  int nz_;                    // number of z variables
  double scale_ = 1.0;        // the rows are divided by this (the first rows' largest entry)
  unsigned environment_ = 0;  // GLPK's environment the problem belongs to
};

}  // namespace tp
