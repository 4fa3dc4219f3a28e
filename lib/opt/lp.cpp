#include "opt/lp.hpp"

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <string>
#include <utility>
#include <vector>

#include <glpk.h>

#include "core/error.hpp"

namespace tp {
namespace {

// GLPK reports an internal error (a failed assertion, an invalid argument) by printing it
// and calling abort().  Its error hook runs first: it longjmps back here instead, and the
// GLPK environment (every problem object with it) is freed, as GLPK's manual prescribes
// for a hook that does not return.  Only C frames of GLPK lie between setjmp and longjmp.
// GLPK's terminal output (which its error path turns back on) goes to a buffer, never to
// stdout: the first line becomes part of our error message.
struct Guard {
  std::jmp_buf env;
  std::string text;
};
thread_local Guard* g_guard = nullptr;
// Counts glp_free_env() calls: a problem object from an earlier environment is gone.
thread_local unsigned g_environment = 0;

void on_error(void*) {
  std::longjmp(g_guard->env, 1);
}
int on_output(void*, const char* s) {
  if (g_guard && g_guard->text.size() < 4096) g_guard->text += s;
  return 1;  // nonzero: GLPK prints nothing itself
}

// Runs fn(args) (GLPK calls only) under the guard; false when GLPK failed.
template <class Fn>
bool guarded(Guard& g, Fn fn) {
  g_guard = &g;
  glp_term_hook(on_output, nullptr);
  glp_error_hook(on_error, nullptr);
  if (setjmp(g.env) != 0) {
    glp_error_hook(nullptr, nullptr);
    glp_term_hook(nullptr, nullptr);
    glp_free_env();  // GLPK's state is undefined after an error: start afresh
    ++g_environment;
    g_guard = nullptr;
    return false;
  }
  fn();
  glp_error_hook(nullptr, nullptr);
  g_guard = nullptr;
  return true;
}

[[noreturn]] void glpk_failed(const Guard& g, const char* what) {
  std::string first = g.text.substr(0, g.text.find('\n'));
  failure(std::string("linear programme solver (GLPK) failed while ") + what +
          (first.empty() ? "" : ": " + first));
}

// Builds the problem without any off-target row: the target equality (row 1) and the
// optional bounds on the weights (rows 2 ..).  C calls only (see guarded()).
void build(glp_prob* lp, int nz, int n_box, double bound, const std::vector<int>& ia,
           const std::vector<int>& ja, const std::vector<double>& ar) {
  glp_term_out(GLP_OFF);
  glp_set_obj_dir(lp, GLP_MIN);
  glp_add_cols(lp, nz + 1);
  for (int j = 1; j <= nz + 1; ++j) glp_set_col_bnds(lp, j, GLP_FR, 0.0, 0.0);
  glp_set_obj_coef(lp, nz + 1, 1.0);
  glp_add_rows(lp, 1 + n_box);
  glp_set_row_bnds(lp, 1, GLP_FX, 1.0, 1.0);
  for (int i = 0; i < n_box; ++i) glp_set_row_bnds(lp, 2 + i, GLP_DB, -bound, bound);
  glp_load_matrix(lp, static_cast<int>(ia.size()) - 1, ia.data(), ja.data(), ar.data());
}

// Appends rows (each nz coefficients): an off-target row with -1 for t, "<= 0"; a capped
// row without t, "<= its cap" (t_coef 0).
void add_rows(glp_prob* lp, int nz, int count, const double* rows, const double* t_coef,
              const double* bound, int* first_row) {
  const int first = glp_add_rows(lp, count);
  *first_row = first;
  std::vector<int> ind(static_cast<std::size_t>(nz) + 2);
  std::vector<double> val(static_cast<std::size_t>(nz) + 2);
  for (int j = 1; j <= nz + 1; ++j) ind[static_cast<std::size_t>(j)] = j;
  for (int r = 0; r < count; ++r) {
    for (int j = 0; j < nz; ++j)
      val[static_cast<std::size_t>(j) + 1] = rows[static_cast<std::size_t>(r) * nz + j];
    val[static_cast<std::size_t>(nz) + 1] = t_coef[r];
    glp_set_mat_row(lp, first + r, t_coef[r] != 0.0 ? nz + 1 : nz, ind.data(), val.data());
    glp_set_row_bnds(lp, first + r, GLP_UP, 0.0, bound[r]);
  }
}

enum class Outcome { optimal, unbounded, infeasible, other };
struct SolveOut {
  Outcome outcome = Outcome::other;
  double value = 0.0;
};

void solve_c(glp_prob* lp, int nz, bool set_target, const int* ind, const double* val, double* z,
             SolveOut* out) {
  if (set_target) glp_set_mat_row(lp, 1, nz, ind, val);
  glp_smcp parm;
  glp_init_smcp(&parm);
  parm.msg_lev = GLP_MSG_OFF;
  parm.meth = GLP_DUALP;
  // Textbook pricing, not projected steepest edge: a focus's LPs (hundreds of rows in the
  // basis, a few dozen columns) took 15 % less time and varied far less (8 x 8 grid, RA:
  // 0.68 +- 0.02 s against 0.79 +- 0.11 s); the paper's array as fast as before.
  parm.pricing = GLP_PT_STD;
  int rc = glp_simplex(lp, &parm);
  if (rc != 0 || glp_get_status(lp) == GLP_UNDEF) {  // retry from scratch once
    glp_std_basis(lp);
    rc = glp_simplex(lp, &parm);
  }
  const int status = glp_get_status(lp);
  if (rc == 0 && status == GLP_OPT) {
    out->outcome = Outcome::optimal;
    out->value = glp_get_obj_val(lp);
    for (int j = 0; j < nz; ++j) z[j] = glp_get_col_prim(lp, j + 1);
    return;
  }
  if (rc == 0 && (status == GLP_UNBND || glp_get_dual_stat(lp) == GLP_NOFEAS))
    out->outcome = Outcome::unbounded;
  else if (rc == 0 && status == GLP_NOFEAS)
    out->outcome = Outcome::infeasible;
  else
    out->outcome = Outcome::other;
  glp_std_basis(lp);  // leave a clean basis for the next call
}

}  // namespace

void release_lp_thread() {
  glp_free_env();
  ++g_environment;
}

void provoke_glpk_error() {
  Guard g;
  glp_prob* lp = nullptr;
  if (!guarded(g, [&] {
        lp = glp_create_prob();
        glp_add_rows(lp, -1);  // GLPK: "invalid number of rows", then abort() without the hook
      }))
    glpk_failed(g, "testing the error hook");
  glp_delete_prob(lp);
}

TargetLp::TargetLp(Eigen::MatrixXd off_rows, const Eigen::MatrixXd& basis, double weight_bound,
                   const Eigen::MatrixXd& capped_rows, const Eigen::VectorXd& caps)
    : nz_(static_cast<int>(off_rows.cols())) {
  if (!basis.allFinite() || !std::isfinite(weight_bound))
    failure("linear programme: non-finite coefficients (a model value out of range)");
  // The ratio is scale invariant: divide every AF row by the largest entry so that GLPK
  // works with numbers near 1 whatever the resistivity, diameters or currents
  // (see solve() for how z and the bound follow; a capped row a z <= c becomes
  // (a / s) (s z) <= c, its cap unchanged).
  double m = off_rows.size() ? off_rows.cwiseAbs().maxCoeff() : 0.0;
  if (capped_rows.size()) m = std::max(m, capped_rows.cwiseAbs().maxCoeff());
  scale_ = m > 0 && std::isfinite(m) ? m : 1.0;
  keep(off_rows, nullptr);
  off_rows = Eigen::MatrixXd();  // kept in rows_: not twice
  keep(capped_rows, &caps);
  const bool box = weight_bound > 0.0;
  const int n_box = box ? static_cast<int>(basis.rows()) : 0;
  std::vector<int> ia{0}, ja{0};
  std::vector<double> ar{0.0};
  for (int j = 0; j < nz_; ++j) {  // the target row: placeholders, replaced by solve()
    ia.push_back(1);
    ja.push_back(j + 1);
    ar.push_back(1.0);
  }
  for (int i = 0; i < n_box; ++i)
    for (int j = 0; j < nz_; ++j) {
      ia.push_back(2 + i);
      ja.push_back(j + 1);
      ar.push_back(basis(i, j));
    }
  Guard g;
  glp_prob* lp = nullptr;
  const double bound = weight_bound * scale_;  // |B z~| <= c s, since z = z~ / s
  if (!guarded(g, [&] {
        lp = glp_create_prob();
        build(lp, nz_, n_box, bound, ia, ja, ar);
      }))
    glpk_failed(g, "setting up the problem");
  lp_ = lp;
  environment_ = g_environment;
  // Start from an even spread of the samples (about 64); solve() adds what it needs.  Each
  // simplex step works on a basis as large as the rows in the LP, so fewer is faster: on
  // the paper's array 64 took 25 % less time than 256, and 32 more (too few rows leave the
  // LP unbounded and cost extra rounds).
  const auto n = static_cast<Eigen::Index>(glp_row_.size());
  std::vector<Eigen::Index> first;
  const Eigen::Index stride = std::max<Eigen::Index>(1, n / 64);
  for (Eigen::Index i = 0; i < n; i += stride) first.push_back(i);
  add(first);
}

void TargetLp::keep(const Eigen::MatrixXd& rows, const Eigen::VectorXd* caps) {
  if (caps && caps->size() != rows.rows())
    failure("linear programme: capped rows and caps disagree");
  if (rows.rows() == 0) return;
  if (rows.cols() != nz_)
    failure("linear programme: rows of " + std::to_string(rows.cols()) + " coefficients, not " +
            std::to_string(nz_));
  if (!rows.allFinite() || (caps && !caps->allFinite()))
    failure("linear programme: non-finite coefficients (a model value out of range)");
  const auto nz = static_cast<std::size_t>(nz_);
  const std::size_t at = rows_.size();
  reserve_spare(rows_, at + static_cast<std::size_t>(rows.rows()) * nz);
  for (Eigen::Index i = 0; i < rows.rows(); ++i) {
    for (Eigen::Index j = 0; j < rows.cols(); ++j) rows_.push_back(rows(i, j) / scale_);
    if (caps) {
      cap_of_.push_back(static_cast<Eigen::Index>(caps_.size()));
      caps_.push_back((*caps)(i));
    } else {
      cap_of_.push_back(-1);
    }
    glp_row_.push_back(0);
  }
}

void TargetLp::append(const Eigen::MatrixXd& off_rows, const Eigen::MatrixXd& capped_rows,
                      const Eigen::VectorXd& caps) {
  keep(off_rows, nullptr);
  keep(capped_rows, &caps);
}

void TargetLp::set_caps(const Eigen::VectorXd& caps) {
  if (caps.size() != static_cast<Eigen::Index>(caps_.size()))
    failure("linear programme: " + std::to_string(caps.size()) + " caps for " +
            std::to_string(caps_.size()) + " capped rows");
  if (!caps.allFinite()) failure("linear programme: non-finite caps");
  if (!lp_ || environment_ != g_environment)
    failure("linear programme: solver state lost after an earlier failure");
  std::vector<int> row;
  std::vector<double> cap;
  for (std::size_t i = 0; i < glp_row_.size(); ++i) {
    const Eigen::Index k = cap_of_[i];
    if (k < 0) continue;
    caps_[static_cast<std::size_t>(k)] = caps(k);
    if (glp_row_[i] > 0) {
      row.push_back(glp_row_[i]);
      cap.push_back(caps(k));
    }
  }
  Guard g;
  glp_prob* lp = lp_;
  if (!guarded(g, [&] {
        for (std::size_t i = 0; i < row.size(); ++i)
          glp_set_row_bnds(lp, row[i], GLP_UP, 0.0, cap[i]);
      })) {
    lp_ = nullptr;
    glpk_failed(g, "changing bounds");
  }
}

void TargetLp::add(const std::vector<Eigen::Index>& rows) {
  if (rows.empty()) return;
  std::vector<double> buf, t_coef, bound;
  const auto nz = static_cast<std::size_t>(nz_);
  buf.reserve(rows.size() * nz);
  for (Eigen::Index i : rows) {
    const auto r = static_cast<std::size_t>(i);
    buf.insert(buf.end(), rows_.begin() + static_cast<std::ptrdiff_t>(r * nz),
               rows_.begin() + static_cast<std::ptrdiff_t>((r + 1) * nz));
    const Eigen::Index k = cap_of_[r];
    t_coef.push_back(k < 0 ? -1.0 : 0.0);
    bound.push_back(k < 0 ? 0.0 : caps_[static_cast<std::size_t>(k)]);
  }
  Guard g;
  glp_prob* lp = lp_;
  const int count = static_cast<int>(rows.size());
  int first = 0;
  if (!guarded(
          g, [&] { add_rows(lp, nz_, count, buf.data(), t_coef.data(), bound.data(), &first); })) {
    lp_ = nullptr;
    glpk_failed(g, "adding constraints");
  }
  for (std::size_t k = 0; k < rows.size(); ++k)
    glp_row_[static_cast<std::size_t>(rows[k])] = first + static_cast<int>(k);
  rows_in_lp_ += rows.size();
}

TargetLp::~TargetLp() {
  if (lp_ && environment_ == g_environment) glp_delete_prob(lp_);
}

std::optional<LpSolution> TargetLp::solve(const Eigen::VectorXd& target_row) {
  if (!lp_ || environment_ != g_environment)
    failure("linear programme: solver state lost after an earlier failure");
  if (!target_row.allFinite())
    failure("linear programme: non-finite target coefficients (a model value out of range)");
  std::vector<int> ind(static_cast<std::size_t>(nz_) + 1);
  std::vector<double> val(static_cast<std::size_t>(nz_) + 1);
  for (int j = 0; j < nz_; ++j) {
    ind[static_cast<std::size_t>(j) + 1] = j + 1;
    val[static_cast<std::size_t>(j) + 1] = target_row(j) / scale_;
  }
  // Constraint generation: solve with the rows in the LP, check every sample, add the most
  // violated, repeat.  The LP with fewer rows is a relaxation, so a solution that violates
  // no sample is the optimum of the whole problem.  Rows stay for later target points (the
  // active sets of nearby points overlap), and each re-solve starts from the last basis.
  Eigen::VectorXd z(nz_);
  const auto n = static_cast<Eigen::Index>(glp_row_.size());
  const std::size_t batch = std::max<std::size_t>(32, static_cast<std::size_t>(nz_));
  for (bool first = true;; first = false) {
    SolveOut out;
    Guard g;
    glp_prob* lp = lp_;
    const int nz = nz_;
    if (!guarded(g, [&] { solve_c(lp, nz, first, ind.data(), val.data(), z.data(), &out); })) {
      lp_ = nullptr;  // freed with GLPK's environment
      glpk_failed(g, "solving");
    }
    std::vector<Eigen::Index> more;
    if (out.outcome == Outcome::optimal) {
      // The excess of each row over its bound: t for an off-target row, its cap otherwise.
      Eigen::VectorXd v =
          Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
              rows_.data(), n, nz_) *
          z;
      for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::Index k = cap_of_[static_cast<std::size_t>(i)];
        v(i) -= k < 0 ? out.value : caps_[static_cast<std::size_t>(k)];
      }
      const double tol = 1e-10 * std::max(1.0, std::fabs(out.value));
      std::vector<std::pair<double, Eigen::Index>> violated;
      // Samples run along the fibres in order: add the peaks of the violation only, not
      // their neighbours, which the next solve satisfies with them.
      for (Eigen::Index i = 0; i < n; ++i)
        if (v(i) > tol && !glp_row_[static_cast<std::size_t>(i)] && (i == 0 || v(i) >= v(i - 1)) &&
            (i + 1 == n || v(i) >= v(i + 1)))
          violated.emplace_back(v(i), i);
      if (violated.empty())  // plateaus: fall back to every violated sample
        for (Eigen::Index i = 0; i < n; ++i)
          if (v(i) > tol && !glp_row_[static_cast<std::size_t>(i)]) violated.emplace_back(v(i), i);
      if (violated.empty()) {
        LpSolution s;
        s.value = out.value;  // t is unchanged by the scaling
        s.z = z / scale_;
        return s;
      }
      const std::size_t k = std::min(batch, violated.size());
      std::partial_sort(violated.begin(), violated.begin() + static_cast<std::ptrdiff_t>(k),
                        violated.end(), [](const auto& a, const auto& b) {
                          return a.first > b.first || (a.first == b.first && a.second < b.second);
                        });
      for (std::size_t i = 0; i < k; ++i) more.push_back(violated[i].second);
    } else if (out.outcome == Outcome::infeasible) {
      return std::nullopt;  // more rows cannot make it feasible
    } else {
      // Unbounded with these rows (or undecided): add twice as many, evenly spread.
      if (rows_in_lp_ == static_cast<std::size_t>(n)) return std::nullopt;
      const std::size_t want = std::max(batch, rows_in_lp_);
      const Eigen::Index stride = std::max<Eigen::Index>(
          1, (n - static_cast<Eigen::Index>(rows_in_lp_)) / static_cast<Eigen::Index>(want));
      for (Eigen::Index i = 0, seen = 0; i < n; ++i)
        if (!glp_row_[static_cast<std::size_t>(i)] && seen++ % stride == 0) more.push_back(i);
    }
    add(more);
  }
}

}  // namespace tp
