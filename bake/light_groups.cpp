#include "bake/light_groups.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace lb {

namespace {

// Every light's group as written, in LightSources order (area lights, lamps, the sky).
std::vector<std::string> source_groups(const Scene& scene, const LightSources& sources) {
  std::vector<std::string> groups;
  for (size_t i = 0; i < sources.size(); ++i) {
    switch (sources.kind(i)) {
      case LightKind::area: {
        const Mesh& mesh = scene.meshes[size_t(sources.area_light(i).mesh)];
        groups.push_back(group_name_or_default(scene.materials[size_t(mesh.material)].light_group));
        break;
      }
      case LightKind::sky:
        groups.push_back(group_name_or_default(scene.sky->light_group));
        break;
      default:
        groups.push_back(group_name_or_default(sources.lamp(i).light_group));
        break;
    }
  }
  return groups;
}

size_t index_of(const std::vector<std::string>& names, const std::string& name) {
  return size_t(std::find(names.begin(), names.end(), name) - names.begin());
}

// `out` += w * `in`, element by element (`out` sized to `in` when empty).
void add_weighted(std::vector<vec3>& out, const std::vector<vec3>& in, float w) {
  if (out.empty()) out.assign(in.size(), vec3(0.0f));
  for (size_t k = 0; k < in.size() && k < out.size(); ++k) out[k] += w * in[k];
}

void scale(std::vector<vec3>& values, float w) {
  for (vec3& v : values) v *= w;
}

}  // namespace

std::vector<std::string> light_group_names(const Scene& scene) {
  const LightSources sources(scene);
  std::vector<std::string> names;
  for (const std::string& group : source_groups(scene, sources))
    if (index_of(names, group) == names.size()) names.push_back(group);
  if (names.size() == 1 && names[0] == kDefaultLightGroup) names.clear();
  return names;
}

std::vector<int> light_group_of_sources(const Scene& scene, const LightSources& sources,
                                        const std::vector<std::string>& names) {
  std::vector<int> out;
  if (names.empty()) return out;
  for (const std::string& group : source_groups(scene, sources))
    out.push_back(int(index_of(names, group)));
  return out;
}

std::vector<LightGroupPower> light_group_powers(const Scene& scene) {
  const LightSources sources(scene);
  std::vector<std::string> names = light_group_names(scene);
  if (names.empty()) names.push_back(kDefaultLightGroup);
  std::vector<LightGroupPower> out;
  for (const std::string& name : names) out.push_back({name, vec3(0.0f), 0});
  const std::vector<std::string> groups = source_groups(scene, sources);
  for (size_t i = 0; i < sources.size(); ++i) {
    LightGroupPower& group = out[std::min(index_of(names, groups[i]), out.size() - 1)];
    group.power += sources.power(i);
    ++group.lights;
  }
  return out;
}

std::vector<LightGroupWeight> parse_group_weights(const std::string& text) {
  std::vector<LightGroupWeight> out;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find(',', start), text.size());
    const std::string entry = text.substr(start, end - start);
    const size_t eq = entry.find('=');
    const std::string name = entry.substr(0, eq);
    const std::string value = eq == std::string::npos ? "" : entry.substr(eq + 1);
    char* parsed_end = nullptr;
    const double w = value.empty() ? NAN : std::strtod(value.c_str(), &parsed_end);
    if (name.empty() || value.empty() || *parsed_end != '\0' || !std::isfinite(w) || w < 0.0)
      throw std::invalid_argument("--group-weights: '" + entry +
                                  "' is not NAME=WEIGHT with a weight >= 0 (e.g. day=0.3,night=2)");
    out.push_back({name, float(w)});
    start = end + 1;
  }
  return out;
}

std::vector<float> resolve_group_weights(const std::vector<std::string>& groups,
                                         const std::vector<LightGroupWeight>& given,
                                         const std::string& scene_path) {
  const std::vector<std::string> names =
      groups.empty() ? std::vector<std::string>{kDefaultLightGroup} : groups;
  std::vector<float> weights(names.size(), 1.0f);
  for (const LightGroupWeight& g : given) {
    const size_t k = index_of(names, g.name);
    if (k == names.size()) {
      std::string known;
      for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("--group-weights: " + scene_path + " has no light group '" +
                                  g.name + "' (its groups: " + known + ")");
    }
    weights[k] = g.weight;
  }
  return weights;
}

Scene scale_light_groups(const Scene& scene, const std::vector<float>& weights) {
  std::vector<std::string> names = light_group_names(scene);
  if (names.empty()) names.push_back(kDefaultLightGroup);
  if (weights.size() != names.size())
    throw std::invalid_argument("light groups: " + std::to_string(weights.size()) +
                                " weights for " + std::to_string(names.size()) + " groups");
  const auto weight_of = [&](const std::string& group) {
    const size_t k = index_of(names, group_name_or_default(group));
    return k < weights.size() ? weights[k] : 1.0f;
  };
  Scene out = scene;
  for (Material& m : out.materials) m.emission *= weight_of(m.light_group);
  for (Lamp& lamp : out.lights) lamp.intensity *= weight_of(lamp.light_group);
  if (out.sky) out.sky->radiance *= weight_of(out.sky->light_group);
  return out;
}

BakeResult blend_light_groups(const BakeResult& bake, const std::vector<float>& weights) {
  BakeResult out = bake;
  const size_t groups = bake.light_groups.size();
  if (groups == 0) {
    if (weights.size() != 1)
      throw std::invalid_argument("light groups: the bake has none, " +
                                  std::to_string(weights.size()) + " weights given");
    scale(out.illumination.radiance, weights[0]);
    for (std::vector<vec3>& axis : out.illumination.l1) scale(axis, weights[0]);
    for (MeshRadiosity& m : out.radiosity.meshes) scale(m.vertex_radiance, weights[0]);
    scale(out.soft_texels.radiance, weights[0]);
    for (std::vector<vec3>& axis : out.soft_texels.l1) scale(axis, weights[0]);
    return out;
  }
  if (weights.size() != groups ||
      (!bake.illumination.radiance.empty() && bake.illumination.group_radiance.size() != groups) ||
      bake.radiosity.group_vertex_radiance.size() != groups ||
      (!bake.soft_texels.radiance.empty() && bake.soft_texels.group_radiance.size() != groups))
    throw std::invalid_argument("light groups: the bake's group layers do not match its " +
                                std::to_string(groups) + " groups");
  out.illumination.radiance.clear();
  out.soft_texels.radiance.clear();
  for (MeshRadiosity& m : out.radiosity.meshes) m.vertex_radiance.clear();
  for (size_t g = 0; g < groups; ++g) {
    if (!bake.illumination.radiance.empty())
      add_weighted(out.illumination.radiance, bake.illumination.group_radiance[g], weights[g]);
    if (!bake.soft_texels.radiance.empty())
      add_weighted(out.soft_texels.radiance, bake.soft_texels.group_radiance[g], weights[g]);
    for (size_t m = 0; m < out.radiosity.meshes.size(); ++m)
      if (m < bake.radiosity.group_vertex_radiance[g].size())
        add_weighted(out.radiosity.meshes[m].vertex_radiance,
                     bake.radiosity.group_vertex_radiance[g][m], weights[g]);
  }
  out.illumination.group_radiance.clear();
  out.soft_texels.group_radiance.clear();
  // The bands are the whole light's, not the blend's: both maps are drawn flat.
  for (std::vector<vec3>& axis : out.illumination.l1) axis.clear();
  out.illumination.l1_share.clear();
  for (std::vector<vec3>& axis : out.soft_texels.l1) axis.clear();
  out.radiosity.group_vertex_radiance.clear();
  out.light_groups.clear();
  return out;
}

}  // namespace lb
