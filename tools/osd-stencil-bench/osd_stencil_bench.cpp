// osd-stencil-bench: times OpenSubdiv's re-posing path, a stencil table, for comparison with
// `subsurf bench --replay` (scripts/bench-vs-osd.sh builds and runs it).
//
//   osd-stencil-bench IN.obj LEVEL REPS
//
// Reads IN.obj (v, f and the OpenSubdiv regression shapes' tags: t crease, corner, hole,
// interpolateboundary, creasemethod, smoothtriangles), refines it uniformly to LEVEL, builds a
// Far::StencilTableReal<double> for the vertices of the last level only, with the weights of the
// intermediate levels factorized onto the control vertices (the table a program would keep to
// re-pose a mesh every frame), then times REPS calls of UpdateValues from the base positions.
// Prints one line:
//   osd stencils level=L verts=N median_s=... min_s=... build_s=... weights=W table_mib=M
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

namespace {

struct Point {
    double x[3];
    void Clear() { x[0] = x[1] = x[2] = 0.0; }
    void AddWithWeight(Point const &p, double w) {
        for (int k = 0; k < 3; ++k) x[k] += w * p.x[k];
    }
};

struct Mesh {
    std::vector<Point> points;
    std::vector<int> sizes, corners;
    std::vector<int> creaseEnds, cornerVerts, holes;
    std::vector<float> creaseSharpness, cornerSharpness;
    int boundary = 2;  // interpolateboundary: 0 none, 1 edge and corner, 2 edge only
    bool chaikin = false, smoothTriangles = false;
};

Mesh read(const char *path) {
    std::ifstream file(path);
    if (!file) {
        std::fprintf(stderr, "osd-stencil-bench: cannot read %s\n", path);
        std::exit(2);
    }
    Mesh m;
    std::string line;
    while (std::getline(file, line)) {
        std::istringstream in(line);
        std::string kind;
        in >> kind;
        if (kind == "v") {
            Point p;
            in >> p.x[0] >> p.x[1] >> p.x[2];
            m.points.push_back(p);
        } else if (kind == "f") {
            std::string item;
            int n = 0;
            while (in >> item) {
                int i = std::atoi(item.c_str());
                m.corners.push_back(i < 0 ? (int)m.points.size() + i : i - 1);
                ++n;
            }
            m.sizes.push_back(n);
        } else if (kind == "t") {
            std::string name, counts;
            in >> name >> counts;
            int ni = 0, nf = 0, ns = 0;
            std::sscanf(counts.c_str(), "%d/%d/%d", &ni, &nf, &ns);
            std::vector<int> ints(ni);
            std::vector<float> floats(nf);
            std::vector<std::string> strings(ns);
            for (int &v : ints) in >> v;
            for (float &v : floats) in >> v;
            for (std::string &v : strings) in >> v;
            auto sharpness = [&](int k) { return nf == 0 ? 10.0f : floats[std::min(k, nf - 1)]; };
            if (name == "crease") {
                for (int k = 0; k + 1 < ni; ++k) {
                    m.creaseEnds.push_back(ints[k]);
                    m.creaseEnds.push_back(ints[k + 1]);
                    m.creaseSharpness.push_back(sharpness(k));
                }
            } else if (name == "corner") {
                for (int k = 0; k < ni; ++k) {
                    m.cornerVerts.push_back(ints[k]);
                    m.cornerSharpness.push_back(sharpness(k));
                }
            } else if (name == "hole") {
                m.holes.insert(m.holes.end(), ints.begin(), ints.end());
            } else if (name == "interpolateboundary" && ni == 1) {
                m.boundary = ints[0];
            } else if (name == "creasemethod" && ns == 1) {
                m.chaikin = strings[0] == "chaikin";
            } else if (name == "smoothtriangles" && ns == 1) {
                m.smoothTriangles = strings[0] == "smooth";
            }
        }
    }
    return m;
}

Far::TopologyRefiner *refiner(Mesh &m) {
    typedef Far::TopologyDescriptor Descriptor;
    Descriptor d;
    d.numVertices = (int)m.points.size();
    d.numFaces = (int)m.sizes.size();
    d.numVertsPerFace = m.sizes.data();
    d.vertIndicesPerFace = m.corners.data();
    d.numCreases = (int)m.creaseSharpness.size();
    d.creaseVertexIndexPairs = m.creaseEnds.data();
    d.creaseWeights = m.creaseSharpness.data();
    d.numCorners = (int)m.cornerSharpness.size();
    d.cornerVertexIndices = m.cornerVerts.data();
    d.cornerWeights = m.cornerSharpness.data();
    d.numHoles = (int)m.holes.size();
    d.holeIndices = m.holes.data();
    Sdc::Options o;
    o.SetVtxBoundaryInterpolation(m.boundary == 0   ? Sdc::Options::VTX_BOUNDARY_NONE
                                  : m.boundary == 1 ? Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                                                    : Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    o.SetCreasingMethod(m.chaikin ? Sdc::Options::CREASE_CHAIKIN : Sdc::Options::CREASE_UNIFORM);
    o.SetTriangleSubdivision(m.smoothTriangles ? Sdc::Options::TRI_SUB_SMOOTH
                                               : Sdc::Options::TRI_SUB_CATMARK);
    return Far::TopologyRefinerFactory<Descriptor>::Create(
        d, Far::TopologyRefinerFactory<Descriptor>::Options(Sdc::SCHEME_CATMARK, o));
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char **argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: osd-stencil-bench IN.obj LEVEL REPS\n");
        return 2;
    }
    int level = std::atoi(argv[2]), reps = std::max(1, std::atoi(argv[3]));
    Mesh mesh = read(argv[1]);
    auto t0 = std::chrono::steady_clock::now();
    Far::TopologyRefiner *r = refiner(mesh);
    if (!r) {
        std::fprintf(stderr, "osd-stencil-bench: OpenSubdiv refused %s\n", argv[1]);
        return 1;
    }
    r->RefineUniform(Far::TopologyRefiner::UniformOptions(level));
    Far::StencilTableFactoryReal<double>::Options options;
    options.generateIntermediateLevels = false;
    options.factorizeIntermediateLevels = true;
    options.generateOffsets = true;
    Far::StencilTableReal<double> const *table =
        Far::StencilTableFactoryReal<double>::Create(*r, options);
    double build = seconds_since(t0);
    int n = table->GetNumStencils();
    std::vector<Point> out(n);
    std::vector<double> times;
    for (int i = 0; i < reps; ++i) {
        auto t1 = std::chrono::steady_clock::now();
        table->UpdateValues(mesh.points.data(), out.data());
        times.push_back(seconds_since(t1));
    }
    std::sort(times.begin(), times.end());
    size_t weights = table->GetWeights().size();
    size_t bytes = weights * (sizeof(double) + sizeof(int)) + (size_t)n * 2 * sizeof(int);
    std::printf("osd stencils level=%d verts=%d median_s=%.6f min_s=%.6f build_s=%.6f weights=%zu table_mib=%zu\n",
                level, n, times[times.size() / 2], times[0], build, weights, bytes >> 20);
    delete table;
    delete r;
    return 0;
}
