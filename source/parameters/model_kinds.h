// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The kinds of model whose entries the parameters layer declares (private
// to source/parameters/). Their models are declared by their owners
// (gait/, wear/), which enter them into these kinds when libtkr is loaded
// (base/registry.h): this layer includes nothing above it.

#ifndef tkr_parameters_model_kinds_h
#define tkr_parameters_model_kinds_h

#include <tkr/base/registry.h>

namespace TKR::Parameters::internal
{
  /** The wear laws (`Wear/Wear law`). */
  inline const ModelKind &
  wear_laws()
  {
    return ModelKind::get("wear law");
  }

  /** The gait protocols (`Gait/Control`). */
  inline const ModelKind &
  gait_protocols()
  {
    return ModelKind::get("gait protocol");
  }
} // namespace TKR::Parameters::internal

#endif
