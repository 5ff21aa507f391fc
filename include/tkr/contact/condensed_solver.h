// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_condensed_solver_h
#define tkr_contact_condensed_solver_h

#include <deal.II/base/index_set.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/vector.h>

#include <tkr/contact/contact_solver.h>
#include <tkr/contact/pose_newton.h>
#include <tkr/elasticity/direct_solver.h>
#include <tkr/elasticity/elastic_system.h>
#include <tkr/mortar/mortar_operator.h>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <unordered_map>
#include <vector>

namespace TKR::Contact
{
  /**
   * The primal-dual active set method of ActiveSetSolver on the contact
   * surface only, for a stiffness matrix K that does not change between
   * many contact solves (the gait cycle: the femur lives in its co-rotated
   * frame and the tibia only translates, so K is the same in every step
   * and pose update).
   *
   * With the mortar operator B (Mortar::MortarOperator) the displacement is
   * u = u_0 - K^{-1} B^T lambda, u_0 = K^{-1} f, and the weighted gaps are
   * g(lambda) = g_0 + W lambda with g_0 = g - B u_0 and the Delassus
   * matrix W = B K^{-1} B^T. A Newton step of the active set A solves the
   * dense system W_AA lambda_A = -g_0,A; the update of the set is the same
   * as ActiveSetSolver's (ActiveSetUpdate), so both solve the same
   * discrete problem.
   *
   * K^{-1} is applied through one sparse Cholesky factorisation
   * (DirectSolver). The columns that W needs, K^{-1} of unit loads in x, y
   * and z at every surface node that an active node's row of B touches,
   * are computed in batches when first needed and kept until the stiffness
   * changes: they do not depend on the geometry of the coupling, so they
   * serve every step, pose update and worn geometry. With a load basis
   * (set_load_basis()) u_0 is a combination of stored solutions too, and a
   * contact solve costs no back substitution at all. The Newton iteration
   * works on the surface values that the rows of covered nodes reference
   * (the contact zone), not on the whole surface.
   *
   * Assumes that K does not couple the two bodies (true: they touch only
   * through the contact constraints); a column that does is refused.
   */
  class CondensedActiveSetSolver : public ContactSolver
  {
  public:
    using ContactSolver::ContactSolver;

    /**
     * Assemble K with the constraints @p dirichlet and the springs of
     * @p loads (they must be the springs of every later solve), factorise
     * it and forget all stored columns.
     */
    void
    setup(const dealii::Mapping<3>                &mapping,
          const dealii::AffineConstraints<double> &dirichlet,
          const Elasticity::BoundaryLoads         &loads) override;

    /** Solve for @p loads: one back substitution for u_0. */
    ContactStatistics
    solve(const dealii::Mapping<3>        &mapping,
          const Elasticity::BoundaryLoads &loads,
          const double                     initial_distance,
          ContactState                    &state) override;

    /** K^{-1} of every basis load, kept until the stiffness changes. */
    void
    set_load_basis(
      const dealii::Mapping<3>                     &mapping,
      const std::vector<Elasticity::BoundaryLoads> &basis) override;

    /** Solve for a combination of the load basis: no back substitution. */
    ContactStatistics
    solve(const dealii::Mapping<3>  &mapping,
          const std::vector<double> &coefficients,
          const double               initial_distance,
          ContactState              &state) override;

    /**
     * The analytic derivatives of the pose equations of @p system: at a
     * contact solution, the Newton step of the multipliers of its active
     * set and the pose together, from the compliance columns (see the .cc
     * file and doc/gait.md). The loads are combinations of the load basis
     * (set_load_basis()) with the coefficients system.load_coefficients();
     * @p initial_distance as in solve().
     */
    std::unique_ptr<PoseDerivatives>
    pose_derivatives(PoseSystem  &system,
                     const double initial_distance) override;

    /**
     * Compute the columns of the nodes whose columns the solves of the
     * last gait cycle before setup() used (remembered by setup()) and of
     * those expect() noted since the last call, in full batches, each
     * group of @p peers a share, and exchange them: the step
     * groups solve interleaved steps of one gait, so they need nearly the
     * same columns. Call after setup(), add_observation() and
     * set_load_basis().
     */
    void
    prefetch(const MPI_Comm peers) override;

    /**
     * Note the surface nodes whose columns the rows of @p slave_nodes in
     * the present coupling need: the next prefetch() computes them too,
     * in full batches, each of its peers a share.
     */
    void
    expect(const std::vector<unsigned int> &slave_nodes) override;

    bool
    wants_expectations() const override
    {
      return n_stored_columns == 0;
    }

    /**
     * Forget which columns the solves used: prefetch() then computes those
     * of the solves from here on. (The first cycle's steps start cold and
     * reach many more nodes on their way than the warm cycles after it: a
     * third of its columns were unused in the cycles that followed.)
     */
    void
    new_cycle() override;

    /** Also forgets the stored columns (they hold the observations). */
    unsigned int
    add_observation(
      const dealii::TrilinosWrappers::MPI::Vector &weights) override;

    /**
     * u = K^{-1} (f - B^T lambda) for the multipliers of the last solve
     * (one more back substitution).
     */
    dealii::TrilinosWrappers::MPI::Vector
    compute_solution() override;

    std::string
    name() const override
    {
      return "condensed active set";
    }

    std::string
    description() const override
    {
      return "condensed active set (sparse Cholesky of the stiffness)";
    }

    /** Number of stored columns of K^{-1}. */
    unsigned int
    n_columns() const
    {
      return n_stored_columns;
    }

  private:
    /**
     * A solution K^{-1} b: its values at the surface DoFs of its own body
     * (the slave's or the master's; the other body's are zero) or of both
     * (load basis), and the observations.
     */
    struct Column
    {
      std::vector<double> surface;
      std::vector<double> observations;
      /** The largest absolute surface value. */
      double peak = 0;
    };

    /**
     * Forget the stored columns; with @p keep_master, the master body's
     * columns stay (their surface values: their observations go, as the
     * observations do at setup()).
     */
    void
    clear_columns(const bool keep_master = false);

    /** The length of @p node's columns: the surface values of its body. */
    unsigned int
    n_own_values(const unsigned int node) const
    {
      return 3 * node < n_slave_values ? n_slave_values : n_master_values;
    }

    /**
     * A fingerprint (64-bit hash over all ranks) of what the master body's
     * columns depend on: its rows of K (columns and values), its surface
     * DoFs and their constraints. Also sets master_body_dofs.
     */
    std::uint64_t
    master_fingerprint();

    /**
     * The mortar operator of the coupling, made again only after the
     * coupling's reinit() (timed as part of the contact zone): the pose
     * iteration's solves share one coupling.
     */
    std::shared_ptr<const Mortar::MortarOperator>
    mortar_operator() const
    {
      dealii::TimerOutput::Scope scope(timer, "contact zone");
      if (!last_operator || operator_generation != coupling.generation())
        {
          last_operator = std::make_shared<Mortar::MortarOperator>(coupling);
          operator_generation = coupling.generation();
        }
      return last_operator;
    }

    /** Compute the columns of the surface nodes @p nodes (x, y, z each). */
    void
    compute_columns(const std::vector<unsigned int> &nodes);

    /**
     * Who sends which node's columns in prefetch(): per peer of @p peers
     * the nodes it sends; @p to_compute gets those this peer computes
     * first (nobody holds them).
     */
    std::vector<std::vector<unsigned int>>
    prefetch_plan(const MPI_Comm             peers,
                  std::vector<unsigned int> &to_compute) const;

    /** Send and receive the columns of prefetch_plan()'s @p sent. */
    void
    exchange_columns(const std::vector<std::vector<unsigned int>> &sent,
                     const MPI_Comm                                peers);

    /**
     * The active-set iteration on the contact zone for the surface
     * displacement @p u0 (all surface values) and its observations.
     */
    ContactStatistics
    iterate(const std::vector<double> &u0,
            const std::vector<double> &u0_observations,
            const double               initial_distance,
            ContactState              &state);

    /**
     * The contact zone of a coupling: the surface values that the rows of
     * the covered nodes reference, and those rows on them.
     */
    struct Zone
    {
      /** The surface values of the zone, increasing (slave ones first). */
      std::vector<unsigned int> values;
      /** How many of them are slave values. */
      unsigned int n_slave = 0;
      /** Per slave node: its row of B on the zone (empty if not covered). */
      std::vector<std::vector<Mortar::MortarOperator::Entry>> rows;
      /** u_0 on the zone. */
      std::vector<double> u0;
      /**
       * Stored columns gathered on the zone's values (see zone_column()),
       * by surface value; each array as long as the zone's part of its
       * body, not initialised before the gather fills it.
       */
      using Gathered =
        std::unordered_map<unsigned int, std::unique_ptr<double[]>>;
      /**
       * The stored columns K^-1 e_c (c a surface value) on the zone's slave
       * values (slave c) or master values (master c), gathered as
       * zone_column() first needs them: a column enters the rows of
       * several active nodes. Shared with the zones of later solves that
       * have the same values (a quarter of them in the gait).
       */
      std::shared_ptr<Gathered> gathered;

      /** Row @p j of B times @p v (values on the zone). */
      double
      apply(const unsigned int j, const std::vector<double> &v) const;

      /**
       * W_AA = B_A Z_A for the @p active nodes and the columns @p z on the
       * zone: row-major, entry (a, b) the row of active[a] times the column
       * of active[b], the same sums as apply().
       */
      std::vector<double>
      delassus(const std::vector<unsigned int> &active,
               const std::vector<Column>       &z) const;
    };

    /**
     * iterate() on the @p zone of @p B, with the columns z_i on it computed
     * so far in @p z (more are added as the active sets need them).
     */
    ContactStatistics
    iterate(const Mortar::MortarOperator &B,
            const Zone                   &zone,
            std::vector<Column>          &z,
            const std::vector<double>    &u0,
            const std::vector<double>    &u0_observations,
            const double                  initial_distance,
            ContactState                 &state);

    /**
     * The values and the gathered columns of the last zone that make_zone()
     * made with new values (forgotten with the stored columns).
     */
    mutable std::vector<unsigned int>       last_zone_values;
    mutable std::shared_ptr<Zone::Gathered> last_gathered;

    /** The zone of the current coupling, with @p u0 on it. */
    Zone
    make_zone(const Mortar::MortarOperator &B,
              const std::vector<double>    &u0) const;

    class AnalyticPose;

    /**
     * The Newton system of multipliers and pose at a contact solution: the
     * rows of its n_active active nodes, then the pose's.
     */
    struct PoseNewtonSystem
    {
      dealii::LAPACKFullMatrix<double> matrix;
      dealii::Vector<double>           rhs;
      unsigned int                     n_active = 0;
    };

    /**
     * A contact solution at a pose on its coupling, as AnalyticPose keeps
     * it: u_0 and the zone there, the columns z_i on the zone computed so
     * far, the active set, and the Newton system once it is needed.
     */
    struct PoseData : PoseDerivatives::Data
    {
      std::vector<double> coefficients;
      /** u_0 on all surface values. */
      std::vector<double> u0;
      std::vector<double> u0_observations;
      Zone                zone;
      std::vector<Column> z;
      std::vector<bool>   active;
      /** The Newton system (empty until newton_step() needs it). */
      std::unique_ptr<PoseNewtonSystem> newton;
    };

    /** How u_0 and the master's points change with the pose. */
    struct PoseSensitivities
    {
      /** du_0/dq_k on the zone and its observations. */
      std::vector<std::vector<double>> u0, observations;
      /** dp/dq_k = L p + v_0 of a master point p. */
      std::vector<std::pair<dealii::Tensor<2, 3>, dealii::Tensor<1, 3>>>
        velocity;
    };

    /** u_0 and the zone at the pose @p q, whose coupling is the current one. */
    std::shared_ptr<PoseData>
    make_pose_data(const PoseSystem &system, const std::vector<double> &q);

    /**
     * The contact solution at the pose of @p point (the active set iteration
     * of solve() on its zone, from the active set of its state): its state,
     * statistics and pose residual, and the active set in @p data.
     */
    void
    solve_at_pose(const PoseSystem       &system,
                  const double            initial_distance,
                  PoseData               &data,
                  PoseDerivatives::Point &point);

    /** du_0/dq and the master's velocity fields at @p point. */
    PoseSensitivities
    pose_sensitivities(const PoseSystem          &system,
                       const std::vector<double> &q,
                       const PoseData            &data) const;

    /**
     * The Newton system of multipliers and pose at the contact solution of
     * the pose @p q (@p data), for its active set.
     */
    PoseNewtonSystem
    pose_newton_system(const PoseSystem          &system,
                       const std::vector<double> &q,
                       PoseData                  &data);

    /**
     * The pose part @p dq of the Newton step of @p newton, damped by
     * @p damping (PoseDerivatives::newton_step()): false if the matrix is
     * (nearly) singular.
     */
    static bool
    solve_newton_system(const PoseSystem       &system,
                        const PoseNewtonSystem &newton,
                        const double            damping,
                        std::vector<double>    &dq);

    /**
     * The stiffness G^-1 of the tray's rigid motions against the pose
     * unknowns' unit forces: G_pk = s_p^-1 r_p(K^-1 f_k), the observations
     * of the load basis columns system.force_columns() without contact.
     */
    dealii::FullMatrix<double>
    rigid_stiffness(const PoseSystem &system) const;

    /** u_0 and its observations for the basis coefficients @p c. */
    void
    combine_basis(const std::vector<double> &c,
                  std::vector<double>       &u0,
                  std::vector<double>       &u0_observations) const;

    /** Compute the columns that the rows of the @p active nodes need. */
    void
    ensure_columns(const Mortar::MortarOperator    &B,
                   const std::vector<unsigned int> &active);

    /** z_i = K^{-1} B_i^T on the zone, with its observations. */
    Column
    zone_column(const Mortar::MortarOperator &B,
                const Zone                   &zone,
                const unsigned int            i) const;

    /**
     * One Newton step for the @p active set: multipliers, pressures and
     * the gaps of the covered nodes into @p state.
     */
    void
    newton_step(const Zone                      &zone,
                const std::vector<unsigned int> &active,
                const std::vector<Column>       &z,
                ContactState                    &state) const;

    /**
     * After the iteration: the slave nodes' displacements, the
     * observations and a bound of the master nodes' displacement.
     */
    void
    finish_state(const Mortar::MortarOperator &B,
                 const std::vector<double>    &u0,
                 const std::vector<double>    &u0_observations,
                 ContactState                 &state);

    /**
     * Values of the columns of @p X at the surface DoFs, on all ranks;
     * column c at offset c * surface size. Constrained DoFs are read from
     * their constraints (without the inhomogeneity) unless X is
     * @p distributed already.
     */
    std::vector<double>
    read_surface(const Epetra_MultiVector &X, const bool distributed) const;

    /** The observations of every column of @p X (column-major, all ranks). */
    std::vector<double>
    observe(const Epetra_MultiVector &X) const;

    /** Add @p value at DoF @p dof of column @p c (through constraints). */
    void
    add_load(Epetra_MultiVector                   &B,
             const unsigned int                    c,
             const dealii::types::global_dof_index dof,
             const double                          value) const;

    /** The stiffness K (with the springs), as factorised. */
    Elasticity::ElasticSystem system{elasticity};
    /** The right-hand side of the inhomogeneous Dirichlet values. */
    dealii::TrilinosWrappers::MPI::Vector dirichlet_rhs;
    Elasticity::DirectSolver              direct_solver;
    /** Slave node DoFs (3 per node) followed by master node DoFs. */
    std::vector<dealii::types::global_dof_index> surface_dofs;
    unsigned int                                 n_slave_values  = 0;
    unsigned int                                 n_master_values = 0;
    /**
     * Per surface node (slave nodes, then master nodes): the columns of
     * unit loads in x, y, z, on its own body's surface values (empty until
     * needed).
     */
    std::vector<std::array<Column, 3>> node_columns;
    unsigned int                       n_stored_columns = 0;
    /**
     * The master body's block of K does not change when only the slave
     * body's geometry does (the wear of the insert): its columns are kept
     * over setup() while master_fingerprint() stays the same.
     */
    std::uint64_t master_block = 0;
    /**
     * The surface nodes that had columns when setup() last forgot them
     * and whose columns the solves since new_cycle() used (prefetch()
     * computes them again), or none if the surfaces changed.
     */
    std::vector<unsigned int> last_stiffness_nodes;
    /** The surface nodes that expect() noted since the last prefetch(). */
    std::vector<bool> expected_nodes;
    /** mortar_operator()'s operator and the coupling's generation it is
     *  of. */
    mutable std::shared_ptr<const Mortar::MortarOperator> last_operator;
    mutable std::uint64_t operator_generation = 0;
    /** Per surface node: whether a solve since new_cycle() (or the last
     *  setup()) used its columns (ensure_columns()). */
    std::vector<bool> used_nodes;
    /** The locally owned DoFs of the master body's cells. */
    dealii::IndexSet master_body_dofs;

    /**
     * The load basis: its right-hand sides (with the Dirichlet part in the
     * last one) and their solutions on both surfaces.
     */
    std::vector<dealii::TrilinosWrappers::MPI::Vector> basis_rhs;
    std::vector<Column>                                basis_columns;
    double                                             basis_residual = 0;

    /**
     * Right-hand side (or basis coefficients, if last_rhs is empty) and
     * contact state of the last solve.
     */
    dealii::TrilinosWrappers::MPI::Vector last_rhs;
    std::vector<double>                   last_coefficients;
    ContactState                          last_state;
  };
} // namespace TKR::Contact

#endif
