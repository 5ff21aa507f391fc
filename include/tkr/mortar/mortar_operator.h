// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_mortar_mortar_operator_h
#define tkr_mortar_mortar_operator_h

#include <deal.II/base/types.h>

#include <tkr/mortar/mortar_coupling.h>

#include <vector>

namespace TKR::Mortar
{
  /**
   * The DoFs of the contact surfaces of @p coupling, three per slave node
   * and then three per master node: the layout of the "surface values"
   * that MortarOperator and the contact solvers work with.
   */
  std::vector<dealii::types::global_dof_index>
  surface_dof_indices(const MortarCoupling &coupling);

  /**
   * The mortar operator B of a MortarCoupling as a sparse matrix: one row
   * per slave node j, one column per displacement DoF of the two contact
   * surfaces ("surface values": three per slave node, then three per master
   * node, in the order of the ContactSurface nodes). Row j holds
   * D_jj n_j on the three DoFs of slave node j and -M_jk n^m_j on those of
   * every master node k it couples to, so that
   *
   *   B_j u = D_jj n_j . u_j - n^m_j . sum_k M_jk u_k
   *
   * is by how much a displacement u closes node j's weighted gap: the gap
   * after deformation is g_j - B_j u (mm^3), and the contact force of
   * multipliers lambda (MPa) is -B^T lambda (N). This is the one place
   * where B is written; every contact solver applies it through this
   * class (rows as constraints, B u for gaps, B^T lambda for forces).
   *
   * Built from the coupling's current state; build it again after every
   * MortarCoupling::reinit().
   */
  class MortarOperator
  {
  public:
    /** One entry of a row: surface value index and value (mm^2). */
    struct Entry
    {
      unsigned int column;
      double       value;
    };

    explicit MortarOperator(const MortarCoupling &coupling);

    /** Number of rows (slave nodes). */
    unsigned int
    n_rows() const
    {
      return row_start.size() - 1;
    }

    /** Number of surface values (columns): 3 x (slave + master nodes). */
    unsigned int
    n_columns() const
    {
      return dofs.size();
    }

    /** Number of slave surface values (the first columns). */
    unsigned int
    n_slave_columns() const
    {
      return n_slave_values;
    }

    /** The global DoF index of every column (surface value). */
    const std::vector<dealii::types::global_dof_index> &
    surface_dofs() const
    {
      return dofs;
    }

    /** The entries of row @p j: first its slave entries, then the master
     * ones. */
    const Entry *
    begin(const unsigned int j) const
    {
      return entries.data() + row_start[j];
    }
    const Entry *
    end(const unsigned int j) const
    {
      return entries.data() + row_start[j + 1];
    }

    /** B_j v for surface values @p v (n_columns() of them). */
    double
    apply_row(const unsigned int j, const double *v) const;

    /**
     * The gap of node j after the displacement @p u (surface values), as a
     * distance: (g_j - B_j u) / D_jj in mm.
     */
    double
    gap(const unsigned int j, const double *u) const;

    /** v += factor B_j^T (surface values). */
    void
    add_row_transpose(const unsigned int j,
                      const double       factor,
                      double            *v) const;

    /** The coupling the operator was built from. */
    const MortarCoupling &
    get_coupling() const
    {
      return coupling;
    }

  private:
    const MortarCoupling                        &coupling;
    std::vector<dealii::types::global_dof_index> dofs;
    unsigned int                                 n_slave_values;
    std::vector<unsigned int>                    row_start;
    std::vector<Entry>                           entries;
  };
} // namespace TKR::Mortar

#endif
