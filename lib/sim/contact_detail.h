#pragma once
// The contact solver's rows (core/contact_rows_detail.h) and their couplings: ContactSolver's own
// state, kept out of the installed sim/contact.h. Internal: included by contact*.cpp alone.
#include <Eigen/Dense>
#include <vector>

#include "sweep/core/contact_rows_detail.h"
#include "sweep/sim/contact.h"

namespace sweep::sim {

struct ContactSolver::RowWork {
  ContactRows ops;                         // the rows' operations and their scratch
  std::vector<ContactRow> normal;          // one per plane, along its normal
  Eigen::MatrixXd by_mass, by_compliance;  // J M⁻¹ Jᵀ and J C Jᵀ over the rows
  Eigen::MatrixXd by_move;                 // J G Jᵀ: the moves' couplings (ContactRows::move_rows)
  ContactRow probe;                        // a station's velocity, one axis at a time
  std::vector<ContactRow> slide;           // friction: two across each pressed contact's normal
  Eigen::MatrixXd slide_by_mass, slide_by_compliance;
  std::vector<ContactRow> stick;  // two across each held pair's normal, then `normal`
  Eigen::MatrixXd stick_by_compliance, stick_by_mass;
};

}  // namespace sweep::sim
