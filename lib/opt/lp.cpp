#include "opt/lp.hpp"

#include <cmath>
#include <csetjmp>
#include <string>
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

// Builds the problem; C calls only (see guarded()).
void build(glp_prob* lp, int nz, int n_off, int n_box, double bound, const std::vector<int>& ia,
           const std::vector<int>& ja, const std::vector<double>& ar) {
  glp_term_out(GLP_OFF);
  const int t_col = nz + 1;
  glp_set_obj_dir(lp, GLP_MIN);
  glp_add_cols(lp, nz + 1);
  for (int j = 1; j <= nz + 1; ++j) glp_set_col_bnds(lp, j, GLP_FR, 0.0, 0.0);
  glp_set_obj_coef(lp, t_col, 1.0);
  glp_add_rows(lp, n_off + 1 + n_box);
  for (int i = 1; i <= n_off; ++i) glp_set_row_bnds(lp, i, GLP_UP, 0.0, 0.0);
  glp_set_row_bnds(lp, n_off + 1, GLP_FX, 1.0, 1.0);
  for (int i = 0; i < n_box; ++i) glp_set_row_bnds(lp, n_off + 2 + i, GLP_DB, -bound, bound);
  glp_load_matrix(lp, static_cast<int>(ia.size()) - 1, ia.data(), ja.data(), ar.data());
}

struct SolveOut {
  bool optimal = false;
  double value = 0.0;
};

void solve_c(glp_prob* lp, int row, int nz, const int* ind, const double* val, double* z,
             SolveOut* out) {
  glp_set_mat_row(lp, row, nz, ind, val);
  glp_smcp parm;
  glp_init_smcp(&parm);
  parm.msg_lev = GLP_MSG_OFF;
  parm.meth = GLP_DUALP;
  int rc = glp_simplex(lp, &parm);
  if (rc != 0 || glp_get_status(lp) != GLP_OPT) {  // retry from scratch once
    glp_std_basis(lp);
    rc = glp_simplex(lp, &parm);
  }
  if (rc != 0 || glp_get_status(lp) != GLP_OPT) {
    glp_std_basis(lp);  // leave a clean basis for the next call
    out->optimal = false;
    return;
  }
  out->optimal = true;
  out->value = glp_get_obj_val(lp);
  for (int j = 0; j < nz; ++j) z[j] = glp_get_col_prim(lp, j + 1);
}

}  // namespace

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

TargetLp::TargetLp(const Eigen::MatrixXd& off_rows, const Eigen::MatrixXd& basis,
                   double weight_bound)
    : nz_(static_cast<int>(off_rows.cols())) {
  if (!off_rows.allFinite() || !basis.allFinite() || !std::isfinite(weight_bound))
    failure("linear programme: non-finite coefficients (a model value out of range)");
  // The ratio is scale invariant: divide every AF row by the largest entry so that GLPK
  // works with numbers near 1 whatever the resistivity, diameters or currents
  // (see solve() for how z and the bound follow).
  const double m = off_rows.cwiseAbs().maxCoeff();
  scale_ = m > 0 ? m : 1.0;
  const int n_off = static_cast<int>(off_rows.rows());
  const bool box = weight_bound > 0.0;
  const int n_box = box ? static_cast<int>(basis.rows()) : 0;
  std::vector<int> ia{0}, ja{0};
  std::vector<double> ar{0.0};
  for (int i = 0; i < n_off; ++i) {
    for (int j = 0; j < nz_; ++j) {
      ia.push_back(i + 1);
      ja.push_back(j + 1);
      ar.push_back(off_rows(i, j) / scale_);
    }
    ia.push_back(i + 1);
    ja.push_back(nz_ + 1);
    ar.push_back(-1.0);
  }
  target_row_ = n_off + 1;
  for (int j = 0; j < nz_; ++j) {  // placeholder coefficients, replaced by solve()
    ia.push_back(target_row_);
    ja.push_back(j + 1);
    ar.push_back(1.0);
  }
  for (int i = 0; i < n_box; ++i)
    for (int j = 0; j < nz_; ++j) {
      ia.push_back(target_row_ + 1 + i);
      ja.push_back(j + 1);
      ar.push_back(basis(i, j));
    }
  Guard g;
  glp_prob* lp = nullptr;
  const double bound = weight_bound * scale_;  // |B z~| <= c s, since z = z~ / s
  if (!guarded(g, [&] {
        lp = glp_create_prob();
        build(lp, nz_, n_off, n_box, bound, ia, ja, ar);
      }))
    glpk_failed(g, "setting up the problem");
  lp_ = lp;
  environment_ = g_environment;
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
  std::vector<double> z(static_cast<std::size_t>(nz_));
  SolveOut out;
  Guard g;
  glp_prob* lp = lp_;
  const int row = target_row_, nz = nz_;
  if (!guarded(g, [&] { solve_c(lp, row, nz, ind.data(), val.data(), z.data(), &out); })) {
    lp_ = nullptr;  // freed with GLPK's environment
    glpk_failed(g, "solving");
  }
  if (!out.optimal) return std::nullopt;
  LpSolution s;
  s.value = out.value;  // t is unchanged by the scaling
  s.z.resize(nz_);
  for (int j = 0; j < nz_; ++j) s.z(j) = z[static_cast<std::size_t>(j)] / scale_;
  return s;
}

}  // namespace tp
