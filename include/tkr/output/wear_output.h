// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_output_wear_output_h
#define tkr_output_wear_output_h

#include <deal.II/fe/mapping.h>

#include <tkr/contact/contact_state.h>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/gait/protocol.h>
#include <tkr/gait/rigid_motion.h>
#include <tkr/gait/step_report.h>
#include <tkr/geometry/worn_geometry.h>
#include <tkr/mortar/contact_surface.h>
#include <tkr/output/summary.h>
#include <tkr/output/vtu_output.h>
#include <tkr/wear/run_result.h>
#include <tkr/wear/wear_state.h>

#include <string>
#include <utility>
#include <vector>

/**
 * The output of the wear problem (DESIGN.md section 6): the screen line of
 * a gait step, `steps.csv`, `wear_history.csv` and the VTU files of the
 * steps and of the wear.
 */
namespace TKR::Output
{
  /**
   * The screen line of gait step @p step of the gait @p protocol (without
   * the wall time if @p testing).
   */
  std::string
  step_line(const unsigned int      step,
            const Gait::StepReport &report,
            const Gait::Protocol   &protocol,
            const bool              testing);

  /**
   * `directory/steps.csv` (`steps_NAME.csv` for the activity @p name of a
   * mix): one row per gait step, with the @p protocol's input and pose
   * columns (written by rank 0).
   */
  void
  write_steps_csv(const std::string                   &directory,
                  const std::vector<Gait::StepReport> &reports,
                  const Gait::Protocol                &protocol,
                  const MPI_Comm                       mpi_communicator,
                  const std::string                   &name = "");

  /**
   * `directory/wear_history.csv` with one row per extrapolation block,
   * numbers with ten significant digits, the columns of each activity of
   * a mix (NAME_mass_mg, ... for the names @p activities, empty without a
   * mix), without the wall time column if @p testing (written by rank 0).
   * Written into a temporary file that is then renamed: it is never half
   * written.
   */
  void
  write_wear_history(const std::string                    &directory,
                     const std::vector<Wear::BlockResult> &rows,
                     const std::vector<std::string>       &activities,
                     const bool                            testing,
                     const MPI_Comm                        mpi_communicator);

  /**
   * A wear run's @p result into @p summary (summary.json, doc/output.md):
   * its named values, the run-in factor's points (run_in_factor) if it
   * has one, and the failed steps (unconverged_steps).
   */
  void
  write_run_result(const Wear::RunResult &result, Summary &summary);

  /** What the VTU file of a gait step shows besides the solution. */
  struct StepFields
  {
    const Mortar::ContactSurface *slave_surface = nullptr;
    const Contact::ContactState  *state         = nullptr;
    Gait::RigidMotion             femur_motion;
    /** Per slave node: slip (mm) and wear depth (pm) to the next step. */
    std::vector<double> slip_to_next, wear_to_next;
  };

  /**
   * Output @p index of @p series: the displacement @p solution (on the
   * DoFHandler of @p elasticity), the contact state, the slip and wear to
   * the next step, and the `motion` field (femur flexed: warp by it in
   * ParaView).
   */
  void
  write_step(const Elasticity::LinearElasticity          &elasticity,
             const dealii::TrilinosWrappers::MPI::Vector &solution,
             const dealii::Mapping<3>                    &mapping,
             const StepFields                            &fields,
             VtuSeries                                   &series,
             const unsigned int                           index);

  /**
   * Named per-vertex fields of the worn tibia after an extrapolation block
   * (indexed by triangulation vertex; values away from tibia_contact are
   * zero), in the order they are written: e.g. the accumulated wear depth
   * (`wear_depth_mm`), the wear rate of the block's cycle
   * (`wear_rate_um_per_Mcycles`), the contact pressure at the step of the
   * largest axial force (`peak_load_pressure_MPa`), the slip over the
   * cycle (`cycle_slip_mm`) and whatever the wear law adds.
   */
  using WornTibiaFields =
    std::vector<std::pair<std::string, std::vector<double>>>;

  /**
   * Output @p index of @p series, at time @p cycles: the tibia alone in its
   * worn geometry (the mesh moved by the wear displacement, which is also
   * written as the vector field `wear_displacement`), with @p fields.
   * Each rank writes its locally owned cells among the @p piece-th of
   * @p n_pieces consecutive shares of the tibia's cells (the step groups
   * each hold the whole worn tibia: each writes a share, in parallel).
   */
  void
  write_worn_tibia(const unsigned int            piece,
                   const unsigned int            n_pieces,
                   const Geometry::WornGeometry &geometry,
                   const WornTibiaFields        &fields,
                   VtuSeries                    &series,
                   const unsigned int            index,
                   const double                  cycles);

  /**
   * `wear_map.csv` (x,y,z,depth_mm,cross_shear per tibia_contact node, worn
   * positions; the cross-shear @p cross_shear of the last cycle, a column
   * only if given for every node) and `wear_map_faces.csv` (its
   * quadrilaterals, node numbers in cyclic order) for scripts/plot-wear, on
   * rank 0. For the activity @p name of a mix, `wear_map_NAME.csv` with
   * the activity's accumulated depth @p depth (per vertex) instead of the
   * geometry's (no faces file: the faces are the same).
   */
  void
  write_wear_map(const std::string            &directory,
                 const Mortar::ContactSurface &surface,
                 const Geometry::WornGeometry &geometry,
                 const std::vector<double>    &cross_shear,
                 const MPI_Comm                mpi_communicator,
                 const std::string            &name  = "",
                 const std::vector<double>    *depth = nullptr);

  /**
   * Run scripts/@p script of the sources with @p arguments (each quoted)
   * on rank 0 of @p mpi_communicator, its output into @p log_file. Returns
   * (on every rank) an empty string on success, else what went wrong.
   */
  std::string
  run_script(const std::string              &script,
             const std::vector<std::string> &arguments,
             const std::string              &log_file,
             const MPI_Comm                  mpi_communicator);

  /**
   * Run scripts/plot-wear on @p directory (rank 0): mass_loss.png with the
   * points of @p measured_file (if not empty) and wear_map.png. Returns an
   * empty string on success, else what went wrong (the caller warns: the
   * plots are a convenience, the results are in the files).
   */
  std::string
  make_plots(const std::string &directory,
             const std::string &measured_file,
             const MPI_Comm     mpi_communicator);
} // namespace TKR::Output

#endif
