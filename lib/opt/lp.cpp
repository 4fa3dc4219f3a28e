#include "opt/lp.hpp"

#include <vector>

#include <glpk.h>

namespace tp {

TargetLp::TargetLp(const Eigen::MatrixXd& off_rows, const Eigen::MatrixXd& basis,
                   double weight_bound)
    : lp_(glp_create_prob()), nz_(static_cast<int>(off_rows.cols())) {
  glp_term_out(GLP_OFF);
  const int n_off = static_cast<int>(off_rows.rows());
  const int t_col = nz_ + 1;
  glp_set_obj_dir(lp_, GLP_MIN);
  glp_add_cols(lp_, nz_ + 1);
  for (int j = 1; j <= nz_ + 1; ++j) glp_set_col_bnds(lp_, j, GLP_FR, 0.0, 0.0);
  glp_set_obj_coef(lp_, t_col, 1.0);

  const bool box = weight_bound > 0.0;
  const int n_box = box ? static_cast<int>(basis.rows()) : 0;
  glp_add_rows(lp_, n_off + 1 + n_box);
  std::vector<int> ia{0}, ja{0};
  std::vector<double> ar{0.0};
  for (int i = 0; i < n_off; ++i) {
    for (int j = 0; j < nz_; ++j) {
      ia.push_back(i + 1);
      ja.push_back(j + 1);
      ar.push_back(off_rows(i, j));
    }
    ia.push_back(i + 1);
    ja.push_back(t_col);
    ar.push_back(-1.0);
    glp_set_row_bnds(lp_, i + 1, GLP_UP, 0.0, 0.0);
  }
  target_row_ = n_off + 1;
  for (int j = 0; j < nz_; ++j) {  // placeholder coefficients, replaced by solve()
    ia.push_back(target_row_);
    ja.push_back(j + 1);
    ar.push_back(1.0);
  }
  glp_set_row_bnds(lp_, target_row_, GLP_FX, 1.0, 1.0);
  for (int i = 0; i < n_box; ++i) {
    for (int j = 0; j < nz_; ++j) {
      ia.push_back(target_row_ + 1 + i);
      ja.push_back(j + 1);
      ar.push_back(basis(i, j));
    }
    glp_set_row_bnds(lp_, target_row_ + 1 + i, GLP_DB, -weight_bound, weight_bound);
  }
  glp_load_matrix(lp_, static_cast<int>(ia.size()) - 1, ia.data(), ja.data(), ar.data());
}

TargetLp::~TargetLp() {
  glp_delete_prob(lp_);
}

std::optional<LpSolution> TargetLp::solve(const Eigen::VectorXd& target_row) {
  std::vector<int> ind(static_cast<std::size_t>(nz_) + 1);
  std::vector<double> val(static_cast<std::size_t>(nz_) + 1);
  for (int j = 0; j < nz_; ++j) {
    ind[static_cast<std::size_t>(j) + 1] = j + 1;
    val[static_cast<std::size_t>(j) + 1] = target_row(j);
  }
  glp_set_mat_row(lp_, target_row_, nz_, ind.data(), val.data());

  glp_smcp parm;
  glp_init_smcp(&parm);
  parm.msg_lev = GLP_MSG_OFF;
  parm.meth = GLP_DUALP;
  int rc = glp_simplex(lp_, &parm);
  if (rc != 0 || glp_get_status(lp_) != GLP_OPT) {  // retry from scratch once
    glp_std_basis(lp_);
    rc = glp_simplex(lp_, &parm);
  }
  if (rc != 0 || glp_get_status(lp_) != GLP_OPT) {
    glp_std_basis(lp_);  // leave a clean basis for the next call
    return std::nullopt;
  }
  LpSolution s;
  s.value = glp_get_obj_val(lp_);
  s.z.resize(nz_);
  for (int j = 0; j < nz_; ++j) s.z(j) = glp_get_col_prim(lp_, j + 1);
  return s;
}

}  // namespace tp
