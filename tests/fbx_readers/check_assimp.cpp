// What assimp (libassimp, Debian's 5.2.5) reads of an FBX file, as JSON on stdout, for
// compare.py: its log's warnings and errors, the node tree, each animation's name, duration,
// ticks per second and channels, the file's UnitScaleFactor, and every node's world position at
// the frames given, evaluated from the first animation's keys the way an engine plays them
// (positions and scalings linear, rotations slerped), at time frame / (frames − 1) × duration.
//
//   g++ -O1 -std=c++17 check_assimp.cpp -o check_assimp $(pkg-config --cflags --libs assimp)
//   check_assimp FILE.fbx FRAMES F1 F2 …      (FRAMES: the take's frame count)
//
// Only assimp's own importer reads the file (no post-processing but its validation step), so
// lengths are the file's units and axes the file's axes; it keeps every curve written (not its
// default of dropping a one-key curve equal to the node's own value).
#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/LogStream.hpp>
#include <assimp/Logger.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/version.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

namespace {

std::vector<std::string> messages;

// Keeps every warning and error assimp logs.
struct Keep : public Assimp::LogStream {
    void write(const char *message) override {
        std::string text(message);
        while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
        messages.push_back(text);
    }
};

std::string json(const std::string &s) {
    std::string out = "\"";
    for (unsigned char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += static_cast<char>(c);
        } else if (c < 0x20) {
            char buffer[8];
            std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
            out += buffer;
        } else {
            out += static_cast<char>(c);
        }
    }
    return out + "\"";
}

std::string number(double v) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.17g", v);
    return buffer;
}

// Index of the last key at or before t (keys ascending), and the fraction toward the next.
template <typename Key>
std::pair<unsigned, double> bracket(const Key *keys, unsigned n, double t) {
    if (n == 0 || t <= keys[0].mTime) return {0, 0.0};
    for (unsigned i = 0; i + 1 < n; ++i) {
        if (t < keys[i + 1].mTime) {
            double span = keys[i + 1].mTime - keys[i].mTime;
            return {i, span > 0 ? (t - keys[i].mTime) / span : 0.0};
        }
    }
    return {n - 1, 0.0};
}

aiVector3D lerp(const aiVectorKey *keys, unsigned n, double t) {
    auto [i, f] = bracket(keys, n, t);
    if (f == 0.0 || i + 1 >= n) return keys[i].mValue;
    return keys[i].mValue + (keys[i + 1].mValue - keys[i].mValue) * static_cast<ai_real>(f);
}

aiQuaternion slerp(const aiQuatKey *keys, unsigned n, double t) {
    auto [i, f] = bracket(keys, n, t);
    if (f == 0.0 || i + 1 >= n) return keys[i].mValue;
    aiQuaternion out;
    aiQuaternion::Interpolate(out, keys[i].mValue, keys[i + 1].mValue, static_cast<ai_real>(f));
    return out.Normalize();
}

// The node's local matrix at time t: from its channel when it has one (a property the channel
// leaves unkeyed keeps the node's own value), else its own.
aiMatrix4x4 local(const aiNode *node, const aiNodeAnim *channel, double t) {
    if (!channel) return node->mTransformation;
    aiVector3D scaling, position;
    aiQuaternion rotation;
    node->mTransformation.Decompose(scaling, rotation, position);
    if (channel->mNumPositionKeys) position = lerp(channel->mPositionKeys, channel->mNumPositionKeys, t);
    if (channel->mNumRotationKeys) rotation = slerp(channel->mRotationKeys, channel->mNumRotationKeys, t);
    if (channel->mNumScalingKeys) scaling = lerp(channel->mScalingKeys, channel->mNumScalingKeys, t);
    return aiMatrix4x4(scaling, rotation, position);
}

// Every node's world position at time t, depth first (the order of `tree`).
void walk(const aiNode *node, const aiMatrix4x4 &parent, const std::map<std::string, const aiNodeAnim *> &channels,
          double t, std::vector<aiVector3D> &out) {
    auto found = channels.find(node->mName.C_Str());
    aiMatrix4x4 world = parent * local(node, found == channels.end() ? nullptr : found->second, t);
    out.emplace_back(world.a4, world.b4, world.c4);
    for (unsigned i = 0; i < node->mNumChildren; ++i) walk(node->mChildren[i], world, channels, t, out);
}

// Every node depth first: its name and its parent's index (−1 for the root).
void tree(const aiNode *node, long parent, std::vector<std::pair<std::string, long>> &out) {
    long self = static_cast<long>(out.size());
    out.emplace_back(node->mName.C_Str(), parent);
    for (unsigned i = 0; i < node->mNumChildren; ++i) tree(node->mChildren[i], self, out);
}

}  // namespace

int main(int argc, char **argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: check_assimp FILE.fbx FRAMES [FRAME …]\n");
        return 2;
    }
    Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
    Assimp::DefaultLogger::get()->attachStream(new Keep, Assimp::Logger::Warn | Assimp::Logger::Err);
    Assimp::Importer importer;
    // Every curve as written: by default assimp drops a curve of one key that equals the node's
    // own value, so a one-frame take at rest would show fewer channels (or none) than written.
    importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_OPTIMIZE_EMPTY_ANIMATION_CURVES, false);
    const aiScene *scene = importer.ReadFile(argv[1], aiProcess_ValidateDataStructure);
    long frames = std::atol(argv[2]);
    std::printf("{\"reader\":\"assimp %u.%u.%u\",", aiGetVersionMajor(), aiGetVersionMinor(), aiGetVersionRevision());
    std::printf("\"messages\":[");
    for (size_t i = 0; i < messages.size(); ++i) std::printf("%s%s", i ? "," : "", json(messages[i]).c_str());
    std::printf("],");
    if (!scene) {
        std::printf("\"error\":%s}\n", json(importer.GetErrorString()).c_str());
        Assimp::DefaultLogger::kill();
        return 1;
    }
    double unit = 0;
    if (scene->mMetaData) {
        float f = 0;
        if (scene->mMetaData->Get("UnitScaleFactor", f)) unit = f;
        double d = 0;
        if (unit == 0 && scene->mMetaData->Get("UnitScaleFactor", d)) unit = d;
    }
    std::printf("\"unit_scale_factor\":%s,", number(unit).c_str());
    std::vector<std::pair<std::string, long>> nodes;
    tree(scene->mRootNode, -1, nodes);
    std::printf("\"nodes\":[");
    for (size_t i = 0; i < nodes.size(); ++i)
        std::printf("%s[%s,%ld]", i ? "," : "", json(nodes[i].first).c_str(), nodes[i].second);
    std::printf("],\"animations\":[");
    for (unsigned a = 0; a < scene->mNumAnimations; ++a) {
        const aiAnimation *anim = scene->mAnimations[a];
        std::printf("%s{\"name\":%s,\"duration\":%s,\"ticks_per_second\":%s,\"channels\":[", a ? "," : "",
                    json(anim->mName.C_Str()).c_str(), number(anim->mDuration).c_str(),
                    number(anim->mTicksPerSecond).c_str());
        for (unsigned c = 0; c < anim->mNumChannels; ++c) {
            const aiNodeAnim *ch = anim->mChannels[c];
            std::printf("%s{\"node\":%s,\"position_keys\":%u,\"rotation_keys\":%u,\"scaling_keys\":%u}", c ? "," : "",
                        json(ch->mNodeName.C_Str()).c_str(), ch->mNumPositionKeys, ch->mNumRotationKeys,
                        ch->mNumScalingKeys);
        }
        std::printf("]}");
    }
    std::printf("],\"frames\":[");
    std::map<std::string, const aiNodeAnim *> channels;
    double duration = 0;
    if (scene->mNumAnimations) {
        const aiAnimation *anim = scene->mAnimations[0];
        duration = anim->mDuration;
        for (unsigned c = 0; c < anim->mNumChannels; ++c)
            channels[anim->mChannels[c]->mNodeName.C_Str()] = anim->mChannels[c];
    }
    for (int k = 3; k < argc; ++k) {
        long frame = std::atol(argv[k]);
        double t = frames > 1 ? duration * static_cast<double>(frame) / static_cast<double>(frames - 1) : 0.0;
        std::vector<aiVector3D> at;
        walk(scene->mRootNode, aiMatrix4x4(), channels, t, at);
        std::printf("%s{\"frame\":%ld,\"time\":%s,\"positions\":[", k > 3 ? "," : "", frame, number(t).c_str());
        for (size_t i = 0; i < at.size(); ++i)
            std::printf("%s[%s,%s,%s]", i ? "," : "", number(at[i].x).c_str(), number(at[i].y).c_str(),
                        number(at[i].z).c_str());
        std::printf("]}");
    }
    std::printf("]}\n");
    Assimp::DefaultLogger::kill();
    return 0;
}
