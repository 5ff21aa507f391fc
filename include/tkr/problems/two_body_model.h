// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_two_body_model_h
#define tkr_problems_two_body_model_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/shared_tria.h>

#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/geometry/worn_geometry.h>
#include <tkr/mortar/mortar_coupling.h>
#include <tkr/output/summary.h>
#include <tkr/parameters/parameters.h>

#include <functional>
#include <memory>
#include <string>

/**
 * The drivers of the `Problem = ...` runs (DESIGN.md section 9): the only
 * code that knows every folder below it. Each driver owns a TwoBodyModel
 * and adds what its problem needs.
 */
namespace TKR::Problems
{
  /**
   * What every problem shares: the parameters, the screen and the timer,
   * the parallel::shared triangulation with both bodies, their geometry
   * (Geometry::WornGeometry: the mesh, moved by the accumulated wear), the
   * two-body LinearElasticity on it, the summary.json record and the wall
   * clock of the run. The verbs frame a run: start(), make_grid(),
   * distribute_dofs(), ..., finish().
   */
  class TwoBodyModel
  {
  public:
    /**
     * A model whose triangulation and solvers live on @p communicator
     * (all ranks, or a step group), while screen output and files come
     * from rank 0 of @p world.
     */
    TwoBodyModel(const Parameters::AllParameters &parameters,
                 const MPI_Comm                   world,
                 const MPI_Comm                   communicator);

    /**
     * Print the title line, create the output directory, record the
     * problem in the summary.
     */
    void
    start(const std::string &title);

    /**
     * Read the mesh into the triangulation (checked), let @p adjust change
     * boundary ids (e.g. roller faces), report the mesh and set up the
     * geometry.
     */
    void
    make_grid(
      const std::function<void(dealii::Triangulation<3> &)> &adjust = {});

    /** Number the DoFs and record their number in the summary. */
    void
    distribute_dofs();

    /**
     * The contact surfaces, `tibia_contact` (slave) and `femur_contact`
     * (master), and their mortar coupling (not yet computed). Call after
     * distribute_dofs(); a second call keeps them (every gait cycle of an
     * activity mix shares them, GaitCycle::setup()).
     */
    void
    setup_contact_surfaces();

    /**
     * Record the ranks, the wall time and @p converged in the summary,
     * write it and say where the results are. Returns @p converged.
     */
    bool
    finish(const bool converged);

    /** The mapping of the current geometry. */
    const dealii::Mapping<3> &
    mapping() const
    {
      return worn_geometry.get_mapping();
    }

    const Parameters::AllParameters &
    parameters() const
    {
      return prm;
    }

    /** All ranks of the run (screen, files). */
    MPI_Comm
    world() const
    {
      return world_communicator;
    }

    /** The ranks that share this model's triangulation and solvers. */
    MPI_Comm
    communicator() const
    {
      return model_communicator;
    }

    /** The screen (rank 0 of world()). */
    const dealii::ConditionalOStream &
    pcout() const
    {
      return screen;
    }

    dealii::TimerOutput &
    timer()
    {
      return timer_output;
    }

    /** Wall time since the model was made (s). */
    double
    wall_time() const
    {
      return wall_timer.wall_time();
    }

    const dealii::Triangulation<3> &
    triangulation() const
    {
      return tria;
    }

    /** The geometry (mesh moved by the accumulated wear). */
    Geometry::WornGeometry &
    geometry()
    {
      return worn_geometry;
    }

    const Geometry::WornGeometry &
    geometry() const
    {
      return worn_geometry;
    }

    const Elasticity::LinearElasticity &
    elasticity() const
    {
      return two_bodies;
    }

    /** `tibia_contact`, after setup_contact_surfaces(). */
    const Mortar::ContactSurface &
    slave_surface() const
    {
      return *slave;
    }

    /** `femur_contact`, after setup_contact_surfaces(). */
    const Mortar::ContactSurface &
    master_surface() const
    {
      return *master;
    }

    /** The mortar coupling, after setup_contact_surfaces(). */
    Mortar::MortarCoupling &
    coupling()
    {
      return *mortar_coupling;
    }

    const Mortar::MortarCoupling &
    coupling() const
    {
      return *mortar_coupling;
    }

    /** The record of summary.json. */
    Output::Summary &
    summary()
    {
      return run_summary;
    }

  private:
    const Parameters::AllParameters           &prm;
    const MPI_Comm                             world_communicator;
    const MPI_Comm                             model_communicator;
    dealii::ConditionalOStream                 screen;
    dealii::TimerOutput                        timer_output;
    dealii::Timer                              wall_timer;
    dealii::parallel::shared::Triangulation<3> tria;
    Geometry::WornGeometry                     worn_geometry;
    Elasticity::LinearElasticity               two_bodies;
    std::unique_ptr<Mortar::ContactSurface>    slave, master;
    std::unique_ptr<Mortar::MortarCoupling>    mortar_coupling;
    Output::Summary                            run_summary;
  };
} // namespace TKR::Problems

#endif
