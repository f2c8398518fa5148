/* The GEnum types of the element properties that choose among named values. Their values, nicks
 * and descriptions come from the core's tables (core/include/jointflow/setting_enums.hpp). */
#pragma once

#include <glib-object.h>

#include "jointflow/settings_schema.hpp"

G_BEGIN_DECLS

GType gst_jointflow_model_type_get_type(void);
GType gst_jointflow_similarity_get_type(void);
GType gst_jointflow_matcher_get_type(void);
GType gst_jointflow_appearance_get_type(void);
GType gst_jointflow_backend_get_type(void);
GType gst_jointflow_target_get_type(void);

G_END_DECLS

namespace jointflow::gst {

/// The GEnum type of an enumeration of the settings schema (enumView<E>()).
GType enumGType(const EnumView& view);

}  // namespace jointflow::gst
