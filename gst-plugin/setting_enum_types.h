/* The GEnum types of the element properties that choose among named values. Their values, nicks
 * and descriptions come from the core's tables (core/include/jointflow/setting_enums.hpp). */
#pragma once

#include <glib-object.h>

#include <vector>

#include "jointflow/settings_schema.hpp"

G_BEGIN_DECLS

GType gst_jointflow_model_type_get_type(void);
GType gst_jointflow_similarity_get_type(void);
GType gst_jointflow_matcher_get_type(void);
GType gst_jointflow_appearance_get_type(void);
GType gst_jointflow_tiles_get_type(void);
GType gst_jointflow_backend_get_type(void);
GType gst_jointflow_target_get_type(void);

G_END_DECLS

namespace jointflow::gst {

/// The GEnum type of an enumeration of settings rows (enumView<E>(), publishMethodView()).
GType enumGType(const EnumView& view);

/// Registers a GEnum named @type_name with the values of @view, kept in @values, which must live
/// as long as the process (a get_type's static): call once, from that get_type.
GType registerEnumType(const char* type_name, const EnumView& view,
                       std::vector<GEnumValue>& values);

}  // namespace jointflow::gst
