// GEnum types from the core's enum tables, with GLib's G_DEFINE_ENUM_TYPE. The macro needs the
// values spelled out; each is taken from the core table by index, and a static_assert stops the
// build when a table grows without its GEnum, so the tables stay the one list of values.
#include "setting_enum_types.h"

#include <gst/gst.h>

#include <string_view>

#include "gstjointflowmetapublish.h"
#include "output_properties.hpp"

using jointflow::EnumInfo;

#define JF_GENUM_VALUE(E, i)                                                                 \
  {                                                                                          \
    static_cast<gint>(EnumInfo<E>::kEntries[i].value), EnumInfo<E>::kEntries[i].description, \
        EnumInfo<E>::kEntries[i].nick                                                        \
  }

static_assert(EnumInfo<jointflow::ModelType>::kEntries.size() == 5, "update the GEnum below");
G_DEFINE_ENUM_TYPE(GstJointFlowModelType, gst_jointflow_model_type,
                   JF_GENUM_VALUE(jointflow::ModelType, 0), JF_GENUM_VALUE(jointflow::ModelType, 1),
                   JF_GENUM_VALUE(jointflow::ModelType, 2), JF_GENUM_VALUE(jointflow::ModelType, 3),
                   JF_GENUM_VALUE(jointflow::ModelType, 4))

static_assert(EnumInfo<jointflow::SimilarityType>::kEntries.size() == 6, "update the GEnum below");
G_DEFINE_ENUM_TYPE(GstJointFlowSimilarity, gst_jointflow_similarity,
                   JF_GENUM_VALUE(jointflow::SimilarityType, 0),
                   JF_GENUM_VALUE(jointflow::SimilarityType, 1),
                   JF_GENUM_VALUE(jointflow::SimilarityType, 2),
                   JF_GENUM_VALUE(jointflow::SimilarityType, 3),
                   JF_GENUM_VALUE(jointflow::SimilarityType, 4),
                   JF_GENUM_VALUE(jointflow::SimilarityType, 5))

static_assert(EnumInfo<jointflow::Matcher>::kEntries.size() == 2, "update the GEnum below");
G_DEFINE_ENUM_TYPE(GstJointFlowMatcher, gst_jointflow_matcher,
                   JF_GENUM_VALUE(jointflow::Matcher, 0), JF_GENUM_VALUE(jointflow::Matcher, 1))

static_assert(EnumInfo<jointflow::AppearanceModel>::kEntries.size() == 3, "update the GEnum below");
G_DEFINE_ENUM_TYPE(GstJointFlowAppearance, gst_jointflow_appearance,
                   JF_GENUM_VALUE(jointflow::AppearanceModel, 0),
                   JF_GENUM_VALUE(jointflow::AppearanceModel, 1),
                   JF_GENUM_VALUE(jointflow::AppearanceModel, 2))

static_assert(EnumInfo<jointflow::TileMode>::kEntries.size() == 3, "update the GEnum below");
G_DEFINE_ENUM_TYPE(GstJointFlowTiles, gst_jointflow_tiles, JF_GENUM_VALUE(jointflow::TileMode, 0),
                   JF_GENUM_VALUE(jointflow::TileMode, 1), JF_GENUM_VALUE(jointflow::TileMode, 2))

static_assert(EnumInfo<jointflow::DnnBackend>::kEntries.size() == 4, "update the GEnum below");
G_DEFINE_ENUM_TYPE(GstJointFlowBackend, gst_jointflow_backend,
                   JF_GENUM_VALUE(jointflow::DnnBackend, 0),
                   JF_GENUM_VALUE(jointflow::DnnBackend, 1),
                   JF_GENUM_VALUE(jointflow::DnnBackend, 2),
                   JF_GENUM_VALUE(jointflow::DnnBackend, 3))

static_assert(EnumInfo<jointflow::DnnTarget>::kEntries.size() == 5, "update the GEnum below");
G_DEFINE_ENUM_TYPE(GstJointFlowTarget, gst_jointflow_target,
                   JF_GENUM_VALUE(jointflow::DnnTarget, 0), JF_GENUM_VALUE(jointflow::DnnTarget, 1),
                   JF_GENUM_VALUE(jointflow::DnnTarget, 2), JF_GENUM_VALUE(jointflow::DnnTarget, 3),
                   JF_GENUM_VALUE(jointflow::DnnTarget, 4))

namespace jointflow::gst {

// By name rather than by address: the view may have been made in another shared object.
GType enumGType(const EnumView& view) {
  const std::string_view what = view.what;
  if (what == EnumInfo<ModelType>::kWhat) return gst_jointflow_model_type_get_type();
  if (what == EnumInfo<SimilarityType>::kWhat) return gst_jointflow_similarity_get_type();
  if (what == EnumInfo<Matcher>::kWhat) return gst_jointflow_matcher_get_type();
  if (what == EnumInfo<AppearanceModel>::kWhat) return gst_jointflow_appearance_get_type();
  if (what == EnumInfo<TileMode>::kWhat) return gst_jointflow_tiles_get_type();
  if (what == EnumInfo<DnnBackend>::kWhat) return gst_jointflow_backend_get_type();
  if (what == EnumInfo<DnnTarget>::kWhat) return gst_jointflow_target_get_type();
  if (what == publishMethodView().what) return gst_jointflow_publish_method_get_type();
  // A new enumeration in the settings schema needs its G_DEFINE_ENUM_TYPE above.
  g_error("jointflow: no GEnum type for the enumeration \"%s\"", view.what);
}

GType registerEnumType(const char* type_name, const EnumView& view,
                       std::vector<GEnumValue>& values) {
  for (const auto& v : view.values) values.push_back({v.value, v.description, v.nick});
  values.push_back({0, nullptr, nullptr});
  return g_enum_register_static(type_name, values.data());
}

}  // namespace jointflow::gst
