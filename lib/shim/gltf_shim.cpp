/*
 * gltf_shim.cpp: a binary glTF (.glb) through tinygltf, built from plain C
 * arrays. Lightmaps travel in each material's extras ("vdbgi_lightmap":
 * texture index, texCoord 1, scale), since glTF has no lightmap slot;
 * AO maps are the core occlusionTexture on texCoord 1.
 */
#include "gltf_shim.h"
#include "gltf_guard.h"
#include "shim.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <vector>

namespace
{

// Append bytes to the one buffer as a view of their own, 4-byte aligned.
int add_view(tinygltf::Model &m, const void *data, size_t size, int target)
{
    std::vector<unsigned char> &buf = m.buffers[0].data;
    while (buf.size() % 4)
        buf.push_back(0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = buf.size();
    v.byteLength = size;
    v.target = target;
    const unsigned char *p = static_cast<const unsigned char *>(data);
    buf.insert(buf.end(), p, p + size);
    m.bufferViews.push_back(v);
    return int(m.bufferViews.size() - 1);
}

int add_accessor(tinygltf::Model &m, const float *data, size_t count, int components, bool bounds)
{
    tinygltf::Accessor a;
    a.bufferView =
        add_view(m, data, count * components * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.count = count;
    a.type = components == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC2;
    if (bounds) { // POSITION must carry min and max
        a.minValues.assign(components, 1e30);
        a.maxValues.assign(components, -1e30);
        for (size_t i = 0; i < count; i++)
            for (int k = 0; k < components; k++) {
                a.minValues[k] = std::min(a.minValues[k], double(data[i * components + k]));
                a.maxValues[k] = std::max(a.maxValues[k], double(data[i * components + k]));
            }
    }
    m.accessors.push_back(a);
    return int(m.accessors.size() - 1);
}

int add_texture(tinygltf::Model &m, int image, int sampler)
{
    tinygltf::Texture t;
    t.source = image;
    t.sampler = sampler;
    m.textures.push_back(t);
    return int(m.textures.size() - 1);
}

} // namespace

/*
 * tinygltf's model filled in one place (about 130 lines, kept whole): every
 * buffer view, accessor, texture and material refers by index to the ones
 * made before it, which reads best as one sequence.
 */
extern "C" vdbgi_result vdbgi_gltf_encode(vdbgi_context *ctx, const vdbgi_gltf_desc *d,
                                          uint8_t **out, size_t *size)
{
    *out = nullptr;
    *size = 0;
    VDBGI_SHIM_BEGIN
    {
        tinygltf::Model m;
        m.asset.version = "2.0";
        m.asset.generator = d->generator ? d->generator : "vdbgi";
        m.buffers.resize(1);
        tinygltf::Sampler s; // linear, clamped: the maps' gutters are made for it
        s.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
        s.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
        s.wrapS = s.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
        m.samplers.push_back(s);
        s.wrapS = s.wrapT = TINYGLTF_TEXTURE_WRAP_REPEAT; // base colour tiles, as the bake read it
        m.samplers.push_back(s);
        for (size_t i = 0; i < d->image_count; i++) {
            tinygltf::Image im;
            im.mimeType = "image/png";
            im.bufferView = add_view(m, d->images[i].png, d->images[i].size, 0);
            m.images.push_back(im);
        }
        bool strength_used = false;
        for (size_t i = 0; i < d->material_count; i++) {
            const vdbgi_gltf_material &src = d->materials[i];
            tinygltf::Material mat;
            mat.pbrMetallicRoughness.baseColorFactor = {src.base[0], src.base[1], src.base[2], 1.0};
            mat.pbrMetallicRoughness.metallicFactor = 0.0;
            mat.pbrMetallicRoughness.roughnessFactor = 1.0;
            mat.doubleSided = src.double_sided;
            if (src.base_texture >= 0) {
                mat.pbrMetallicRoughness.baseColorTexture.index =
                    add_texture(m, src.base_texture, 1);
                mat.pbrMetallicRoughness.baseColorTexture.texCoord = 0;
            }
            const float peak = std::max({src.emissive[0], src.emissive[1], src.emissive[2]});
            if (peak > 0.0f) {
                const float f = peak > 1.0f ? peak : 1.0f;
                mat.emissiveFactor = {src.emissive[0] / f, src.emissive[1] / f,
                                      src.emissive[2] / f};
                if (f > 1.0f) {
                    tinygltf::Value::Object strength;
                    strength["emissiveStrength"] = tinygltf::Value(double(f));
                    mat.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(strength);
                    strength_used = true;
                }
                if (src.emissive_texture >= 0) {
                    mat.emissiveTexture.index = add_texture(m, src.emissive_texture, 1);
                    mat.emissiveTexture.texCoord = 0;
                }
            }
            if (src.map >= 0) {
                const int tex = add_texture(m, src.map, 0);
                if (d->ao) {
                    mat.occlusionTexture.index = tex;
                    mat.occlusionTexture.texCoord = 1;
                } else {
                    tinygltf::Value::Object lm;
                    lm["texture"] = tinygltf::Value(tex);
                    lm["texCoord"] = tinygltf::Value(1);
                    lm["scale"] = tinygltf::Value(double(d->map_scale));
                    tinygltf::Value::Array layers;
                    for (size_t l = 0; src.layer_maps && l < d->layer_count; l++) {
                        tinygltf::Value::Object layer;
                        layer["name"] = tinygltf::Value(std::string(d->layer_names[l]));
                        layer["texture"] = tinygltf::Value(add_texture(m, src.layer_maps[l], 0));
                        layer["scale"] = tinygltf::Value(double(d->layer_scales[l]));
                        layers.push_back(tinygltf::Value(layer));
                    }
                    if (!layers.empty())
                        lm["layers"] = tinygltf::Value(layers);
                    tinygltf::Value::Object extras;
                    extras["vdbgi_lightmap"] = tinygltf::Value(lm);
                    mat.extras = tinygltf::Value(extras);
                }
            }
            m.materials.push_back(mat);
        }
        if (strength_used)
            m.extensionsUsed.push_back("KHR_materials_emissive_strength");
        const int pos = add_accessor(m, d->positions, d->vertex_count, 3, true);
        const int nrm = add_accessor(m, d->normals, d->vertex_count, 3, false);
        const int uv0 = d->uv0 ? add_accessor(m, d->uv0, d->vertex_count, 2, false) : -1;
        const int uv1 = add_accessor(m, d->uv1, d->vertex_count, 2, false);
        const int col = d->colors ? add_accessor(m, d->colors, d->vertex_count, 3, false) : -1;
        tinygltf::Mesh mesh;
        for (size_t i = 0; i < d->primitive_count; i++) {
            const vdbgi_gltf_primitive &p = d->primitives[i];
            // Each primitive reads its own range of the shared vertex arrays through indices.
            std::vector<uint32_t> idx(p.count);
            for (uint32_t k = 0; k < p.count; k++)
                idx[k] = p.first + k;
            tinygltf::Accessor ia;
            ia.bufferView =
                add_view(m, idx.data(), idx.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
            ia.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
            ia.count = idx.size();
            ia.type = TINYGLTF_TYPE_SCALAR;
            m.accessors.push_back(ia);
            tinygltf::Primitive prim;
            prim.attributes["POSITION"] = pos;
            prim.attributes["NORMAL"] = nrm;
            if (uv0 >= 0)
                prim.attributes["TEXCOORD_0"] = uv0;
            prim.attributes["TEXCOORD_1"] = uv1;
            if (col >= 0)
                prim.attributes["COLOR_0"] = col;
            prim.indices = int(m.accessors.size() - 1);
            prim.material = int(p.material);
            prim.mode = TINYGLTF_MODE_TRIANGLES;
            mesh.primitives.push_back(prim);
        }
        m.meshes.push_back(mesh);
        tinygltf::Node node;
        node.mesh = 0;
        m.nodes.push_back(node);
        tinygltf::Scene scene;
        scene.nodes.push_back(0);
        m.scenes.push_back(scene);
        m.defaultScene = 0;
        std::ostringstream os;
        tinygltf::TinyGLTF writer;
        if (!writer.WriteGltfSceneToStream(&m, os, false, true))
            return vdbgi_fail(ctx, VDBGI_ERR_BACKEND, "glTF: tinygltf could not write the .glb");
        const std::string bytes = os.str();
        *out = static_cast<uint8_t *>(vdbgi_alloc(ctx, bytes.size() ? bytes.size() : 1));
        if (!*out)
            return VDBGI_ERR_OUT_OF_MEMORY;
        std::memcpy(*out, bytes.data(), bytes.size());
        *size = bytes.size();
        return VDBGI_OK;
    }
    VDBGI_SHIM_END(ctx, "glTF")
}

/*
 * The glTF at path (by its name) into m: true when it is one and parses;
 * false for another kind (VDBGI_OK in *r) or with the failure in *r.
 */
static bool load_model(vdbgi_context *ctx, const char *path, tinygltf::Model &m, vdbgi_result *r)
{
    *r = VDBGI_OK;
    const bool glb = vdbgi_gltf_named(path, ".glb");
    if (!glb && !vdbgi_gltf_named(path, ".gltf"))
        return false;
    tinygltf::TinyGLTF loader;
    vdbgi_gltf_guard_files(loader);
    std::string error, warning;
    const bool ok = glb ? loader.LoadBinaryFromFile(&m, &error, &warning, path)
                        : loader.LoadASCIIFromFile(&m, &error, &warning, path);
    if (!ok)
        *r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s",
                        error.empty() ? "tinygltf cannot read it" : error.c_str());
    return ok;
}

extern "C" vdbgi_result vdbgi_gltf_light_ranges(vdbgi_context *ctx, const char *path, float **out,
                                                size_t *count)
{
    *out = nullptr;
    *count = 0;
    VDBGI_SHIM_BEGIN
    tinygltf::Model m;
    vdbgi_result r;
    if (!load_model(ctx, path, m, &r) || m.lights.empty())
        return r;
    float *const ranges = static_cast<float *>(vdbgi_calloc(ctx, m.lights.size(), sizeof(float)));
    if (!ranges)
        return VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t i = 0; i < m.lights.size(); i++) {
        const double v = m.lights[i].range;
        ranges[i] = v > 3e38 ? HUGE_VALF : v < -3e38 ? -HUGE_VALF : float(v);
    }
    *out = ranges;
    *count = m.lights.size();
    return VDBGI_OK;
    VDBGI_SHIM_END(ctx, "glTF")
}

extern "C" vdbgi_result vdbgi_gltf_materials(vdbgi_context *ctx, const char *path,
                                             vdbgi_gltf_material_info **out, size_t *count)
{
    *out = nullptr;
    *count = 0;
    VDBGI_SHIM_BEGIN
    tinygltf::Model m;
    vdbgi_result r;
    if (!load_model(ctx, path, m, &r) || m.materials.empty())
        return r;
    vdbgi_gltf_material_info *const info = static_cast<vdbgi_gltf_material_info *>(
        vdbgi_calloc(ctx, m.materials.size(), sizeof(vdbgi_gltf_material_info)));
    if (!info)
        return VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t i = 0; i < m.materials.size(); i++) {
        const tinygltf::Material &src = m.materials[i];
        vdbgi_gltf_material_info &o = info[i];
        o = vdbgi_gltf_material_info{};
        if (src.name.size() < sizeof(o.name))
            std::memcpy(o.name, src.name.c_str(), src.name.size() + 1);
        for (int k = 0; k < 3; k++) {
            o.emissive[k] =
                k < int(src.emissiveFactor.size()) ? float(src.emissiveFactor[k]) : 0.0f;
            const auto &b = src.pbrMetallicRoughness.baseColorFactor;
            o.base[k] = k < int(b.size()) ? float(b[k]) : 1.0f;
        }
        o.strength = 1.0f;
        const auto ext = src.extensions.find("KHR_materials_emissive_strength");
        if (ext != src.extensions.end()) {
            const tinygltf::Value &v = ext->second.Get("emissiveStrength");
            // As written: the importer refuses a negative one and caps a large one.
            const double d = v.IsNumber() ? v.GetNumberAsDouble() : 1.0;
            o.strength = d > 3e38 ? HUGE_VALF : float(d);
        }
    }
    *out = info;
    *count = m.materials.size();
    return VDBGI_OK;
    VDBGI_SHIM_END(ctx, "glTF")
}
