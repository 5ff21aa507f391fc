// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_output_wear_output_h
#define tkr_output_wear_output_h

#include <deal.II/fe/mapping.h>

#include <tkr/contact/contact_state.h>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/gait/rigid_motion.h>
#include <tkr/mortar/contact_surface.h>
#include <tkr/output/vtu_output.h>
#include <tkr/wear/step_record.h>

#include <string>
#include <vector>

/**
 * The output of the wear problem (DESIGN.md section 6): the screen line of
 * a gait step, `steps.csv`, `wear_history.csv` and the VTU files of the
 * steps and of the wear.
 */
namespace TKR::Output
{
  /**
   * The screen line of gait step @p step (without the wall time if
   * @p testing).
   */
  std::string
  step_line(const unsigned int      step,
            const Wear::StepReport &report,
            const bool              testing);

  /** `directory/steps.csv`: one row per gait step (written by rank 0). */
  void
  write_steps_csv(const std::string                   &directory,
                  const std::vector<Wear::StepReport> &reports,
                  const MPI_Comm                       mpi_communicator);

  /** One row of `wear_history.csv`: the state after an extrapolation block. */
  struct WearHistoryRow
  {
    unsigned int block  = 0;
    double       cycles = 0;
    /** Worn volume (mm^3) and mass (mg) so far. */
    double volume = 0, mass = 0;
    /** Largest wear depth so far (mm). */
    double max_depth = 0;
    /** Worn part of tibia_contact (%). */
    double wear_area_percent = 0;
    /** Peak pressure (MPa) and largest contact area (mm^2) of the cycle. */
    double peak_pressure = 0, max_contact_area = 0;
    /** Wall time of the run so far (s). */
    double wall_time = 0;
  };

  /**
   * `directory/wear_history.csv`, one row per extrapolation block, numbers
   * with ten significant digits; without the wall time column if
   * @p testing. The whole file is written again at every append, into a
   * temporary file that is then renamed: it is never half written.
   */
  class WearHistory
  {
  public:
    WearHistory(const std::string &directory,
                const bool         testing,
                const MPI_Comm     mpi_communicator);

    void
    append(const WearHistoryRow &row);

  private:
    const std::string           filename;
    const bool                  testing;
    const MPI_Comm              mpi_communicator;
    std::vector<WearHistoryRow> rows;
  };

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
   * Output @p index of @p series: the solution in @p elasticity, the
   * contact state, the slip and wear to the next step, and the `motion`
   * field (femur flexed: warp by it in ParaView).
   */
  void
  write_step(const Elasticity::LinearElasticity &elasticity,
             const dealii::Mapping<3>           &mapping,
             const StepFields                   &fields,
             VtuSeries                          &series,
             const unsigned int                  index);
} // namespace TKR::Output

#endif
