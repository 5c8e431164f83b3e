/* embree_rays: time Embree's single-ray closest-hit (rtcIntersect1) and occlusion (rtcOccluded1) queries on one
 * thread, on the ray sets `prism bench --export-rays DIR` writes (DIR/SCENE.prism-rays; layout in Prism's
 * src/accel/ray_file.rs), and check Embree's answers against Prism's.
 *
 *   embree_rays FILE.prism-rays [--seconds S] [--robust] [--quality medium|high] [--passes N] [--verbose]
 *
 * Build (benches/embree/embree_compare.py does this): gcc -O2 -o embree_rays embree_rays.c -lembree3 (or -lembree4
 * with -DEMBREE4 and <embree4/rtcore.h>).
 *
 * The scene is one triangle geometry (triangle i of the file is primID i) built with RTC_BUILD_QUALITY_HIGH
 * (the scene's and the geometry's; --quality medium: RTC_BUILD_QUALITY_MEDIUM, binned SAH without spatial splits), scene flags none (or RTC_SCENE_FLAG_ROBUST with --robust), on a device made
 * with "threads=1". Timing mirrors `prism bench`: rounds in which every ray set (camera and bounce rays: closest
 * hit, shadow rays: occlusion) is traced once in a plain loop over single rays, until each set has had at least S
 * seconds and at least 3 rounds were done; each number is the fastest pass. --passes N instead does exactly N
 * rounds (0: none), for counting one pass's work under valgrind --tool=cachegrind (the difference of two counts). Output: a human-readable summary on
 * stderr and one JSON line on stdout:
 *   {"embree": "3.13.5", "tris": T, "build_ms": ..., "sets": [{"kind": "camera", "rays": N, "best_s": ...,
 *    "mrays": ..., "agree": ..., "self_hits": ..., "checked": ...}, ...]}
 * "agree" counts the rays on which Embree and Prism give the same answer: both miss, or both hit with the same
 * primitive or |t - t_prism| <= 1e-4 t (closest hit); the same occlusion answer (shadow rays). "self_hits" counts
 * the other rays on which Embree hit within 1e-4 (times the origin's magnitude, at least 1) of the origin and
 * agrees with Prism once it ignores that stretch: the surface the ray leaves, found again by Embree's test from
 * tnear = 0 (Prism offsets spawned rays by its rounding-error bound and finds nothing there). --verbose prints
 * every disagreement.
 */
#ifdef EMBREE4
#include <embree4/rtcore.h>
#else
#include <embree3/rtcore.h>
#endif
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct {
    float o[3], d[3], tmax;
} Ray7;

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void die(const char *msg, const char *path) {
    fprintf(stderr, "error: %s: %s\n", path, msg);
    exit(1);
}

static uint32_t rd_u32(const unsigned char *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float rd_f32(const unsigned char *p) {
    uint32_t u = rd_u32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static void on_error(void *user, enum RTCError code, const char *str) {
    (void)user;
    fprintf(stderr, "error: embree %d: %s\n", (int)code, str ? str : "");
    exit(1);
}

static inline void ray_init(struct RTCRay *r, const Ray7 *s, float tnear) {
    r->org_x = s->o[0];
    r->org_y = s->o[1];
    r->org_z = s->o[2];
    r->tnear = tnear;
    r->dir_x = s->d[0];
    r->dir_y = s->d[1];
    r->dir_z = s->d[2];
    r->time = 0.0f;
    r->tfar = s->tmax;
    r->mask = 0xffffffffu;
    r->id = 0;
    r->flags = 0;
}

/* Closest hit of one ray beyond `tnear` (0 when timed): primID (or UINT32_MAX) and t. */
static inline uint32_t closest(RTCScene scene, const Ray7 *s, float tnear, float *t) {
    struct RTCRayHit rh;
    ray_init(&rh.ray, s, tnear);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
#ifdef EMBREE4
    rtcIntersect1(scene, &rh, NULL);
#else
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcIntersect1(scene, &ctx, &rh);
#endif
    *t = rh.ray.tfar;
    return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? UINT32_MAX : rh.hit.primID;
}

static inline int occluded(RTCScene scene, const Ray7 *s, float tnear) {
    struct RTCRay r;
    ray_init(&r, s, tnear);
#ifdef EMBREE4
    rtcOccluded1(scene, &r, NULL);
#else
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcOccluded1(scene, &ctx, &r);
#endif
    return r.tfar < 0.0f; /* Embree sets tfar to -inf when the ray is blocked */
}

/* One pass over a set; returns seconds. `sink` keeps the work observable. */
static double pass(RTCScene scene, const Ray7 *rays, uint32_t n, int shadow, uint64_t *sink) {
    uint64_t acc = 0;
    double t0 = now();
    if (shadow) {
        for (uint32_t i = 0; i < n; i++) acc += (uint64_t)occluded(scene, &rays[i], 0.0f);
    } else {
        float t;
        for (uint32_t i = 0; i < n; i++) acc += closest(scene, &rays[i], 0.0f, &t);
    }
    double dt = now() - t0;
    *sink += acc;
    return dt;
}

int main(int argc, char **argv) {
    const char *path = NULL;
    double seconds = 0.5;
    int robust = 0, verbose = 0, passes = -1;
    enum RTCBuildQuality quality = RTC_BUILD_QUALITY_HIGH;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--seconds") && i + 1 < argc) {
            seconds = atof(argv[++i]);
        } else if (!strcmp(argv[i], "--robust")) {
            robust = 1;
        } else if (!strcmp(argv[i], "--quality") && i + 1 < argc) {
            const char *q = argv[++i];
            if (strcmp(q, "medium") && strcmp(q, "high")) {
                fprintf(stderr, "--quality: expected medium or high, got '%s'\n", q);
                return 2;
            }
            quality = !strcmp(q, "medium") ? RTC_BUILD_QUALITY_MEDIUM : RTC_BUILD_QUALITY_HIGH;
        } else if (!strcmp(argv[i], "--passes") && i + 1 < argc) {
            char *end = NULL;
            long n = strtol(argv[++i], &end, 10);
            if (!end || *end || n < 0 || n > 1000000) {
                fprintf(stderr, "--passes: expected a count from 0 to 1000000\n");
                return 2;
            }
            passes = (int)n;
        } else if (!strcmp(argv[i], "--verbose")) {
            verbose = 1;
        } else if (argv[i][0] != '-' && !path) {
            path = argv[i];
        } else {
            fprintf(stderr, "usage: embree_rays FILE.prism-rays [--seconds S] [--robust] [--quality medium|high] "
                            "[--passes N] [--verbose]\n");
            return 2;
        }
    }
    if (!path || !(seconds > 0.0)) {
        fprintf(stderr, "usage: embree_rays FILE.prism-rays [--seconds S] [--robust] [--quality medium|high] "
                            "[--passes N] [--verbose]\n");
        return 2;
    }

    FILE *f = fopen(path, "rb");
    if (!f) die("cannot open", path);
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    if (len < 28) die("not a Prism ray-set file (too short)", path);
    unsigned char *buf = malloc((size_t)len);
    if (!buf || fread(buf, 1, (size_t)len, f) != (size_t)len) die("cannot read", path);
    fclose(f);
    if (memcmp(buf, "PRSMRAYS", 8) != 0) die("not a Prism ray-set file (bad magic)", path);
    if (rd_u32(buf + 8) != 1) die("unsupported version (expected 1)", path);
    uint64_t nt = rd_u32(buf + 12), nc = rd_u32(buf + 16), nb = rd_u32(buf + 20), ns = rd_u32(buf + 24);
    uint64_t expect = 28 + nt * 36 + (nc + nb + ns) * 28 + (nc + nb) * 8 + ns * 4;
    if ((uint64_t)len != expect) die("length does not match its header", path);

    RTCDevice device = rtcNewDevice("threads=1");
    if (!device) die("rtcNewDevice failed", path);
    rtcSetDeviceErrorFunction(device, on_error, NULL);
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, quality);
    rtcSetSceneFlags(scene, robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(geom, quality);
    float *vb = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, nt * 3);
    unsigned *ib = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, nt);
    const unsigned char *p = buf + 28;
    for (uint64_t i = 0; i < nt * 9; i++, p += 4) vb[i] = rd_f32(p);
    for (uint64_t i = 0; i < nt * 3; i++) ib[i] = (unsigned)i;
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    double b0 = now();
    rtcCommitScene(scene);
    double build_ms = (now() - b0) * 1e3;

    uint64_t counts[3] = {nc, nb, ns};
    Ray7 *sets[3];
    for (int s = 0; s < 3; s++) {
        sets[s] = malloc(sizeof(Ray7) * (counts[s] ? counts[s] : 1));
        for (uint64_t i = 0; i < counts[s]; i++) {
            float v[7];
            for (int k = 0; k < 7; k++, p += 4) v[k] = rd_f32(p);
            memcpy(sets[s][i].o, v, 12);
            memcpy(sets[s][i].d, v + 3, 12);
            sets[s][i].tmax = v[6];
        }
    }
    /* Check Embree's answers against Prism's. A disagreement that goes away when Embree ignores hits within
     * SELF_T of the origin (scaled by the origin's magnitude) is counted as an Embree self-hit: the ray leaves a
     * surface (bounce and shadow rays start on one, offset by Prism's rounding-error bound) and Embree, asked from
     * tnear = 0 as it is timed, finds that surface again at t ~ 1e-9..1e-5. */
    const float SELF_T = 1e-4f;
    uint64_t agree[3] = {0, 0, 0}, self_hits[3] = {0, 0, 0};
    for (int s = 0; s < 2; s++) {
        for (uint64_t i = 0; i < counts[s]; i++, p += 8) {
            uint32_t prim = rd_u32(p);
            float tp = rd_f32(p + 4), t;
            uint32_t e = closest(scene, &sets[s][i], 0.0f, &t);
            int same = (prim == UINT32_MAX || e == UINT32_MAX) ? prim == e : (prim == e || fabsf(t - tp) <= 1e-4f * tp);
            agree[s] += same;
            if (!same) {
                const Ray7 *r = &sets[s][i];
                float scale = fmaxf(1.0f, fmaxf(fabsf(r->o[0]), fmaxf(fabsf(r->o[1]), fabsf(r->o[2]))));
                float t2;
                uint32_t e2 = closest(scene, r, SELF_T * scale, &t2);
                int same2 = (prim == UINT32_MAX || e2 == UINT32_MAX) ? prim == e2
                                                                    : (prim == e2 || fabsf(t2 - tp) <= 1e-4f * tp);
                self_hits[s] += same2 && t < SELF_T * scale;
                if (verbose)
                    fprintf(stderr, "set %d ray %llu: Prism prim %d t %g, Embree prim %d t %g%s\n", s,
                            (unsigned long long)i, (int)prim, tp, (int)e, t,
                            same2 && t < SELF_T * scale ? " (self-hit)" : "");
            }
        }
    }
    for (uint64_t i = 0; i < ns; i++, p += 4) {
        int po = rd_u32(p) != 0, eo = occluded(scene, &sets[2][i], 0.0f);
        agree[2] += po == eo;
        if (po != eo) {
            const Ray7 *r = &sets[2][i];
            float scale = fmaxf(1.0f, fmaxf(fabsf(r->o[0]), fmaxf(fabsf(r->o[1]), fabsf(r->o[2]))));
            int self = !po && !occluded(scene, r, SELF_T * scale);
            self_hits[2] += self;
            if (verbose)
                fprintf(stderr, "shadow ray %llu (tmax %g): Prism %s, Embree %s%s\n", (unsigned long long)i,
                        r->tmax, po ? "occluded" : "clear", eo ? "occluded" : "clear", self ? " (self-hit)" : "");
        }
    }

    /* Interleaved timing: best pass per set. */
    double best[3] = {INFINITY, INFINITY, INFINITY}, spent[3] = {0, 0, 0};
    uint64_t sink = 0;
    for (int round = 0;; round++) {
        int more = 0;
        for (int s = 0; s < 3; s++) {
            if (!counts[s] || (passes >= 0 ? round >= passes : round >= 3 && spent[s] >= seconds)) continue;
            double dt = pass(scene, sets[s], (uint32_t)counts[s], s == 2, &sink);
            if (dt < best[s]) best[s] = dt;
            spent[s] += dt;
            more = 1;
        }
        if (!more) break;
    }
    const char *kinds[3] = {"camera", "bounce", "shadow"};
    printf("{\"embree\": \"%s\", \"robust\": %s, \"tris\": %llu, \"build_ms\": %.3f, \"sets\": [", RTC_VERSION_STRING,
           robust ? "true" : "false", (unsigned long long)nt, build_ms);
    for (int s = 0; s < 3; s++) {
        double mr = counts[s] ? counts[s] / best[s] / 1e6 : 0.0;
        printf("%s{\"kind\": \"%s\", \"rays\": %llu, \"best_s\": %.6f, \"mrays\": %.4f, \"agree\": %llu, "
               "\"self_hits\": %llu, \"checked\": %llu}",
               s ? ", " : "", kinds[s], (unsigned long long)counts[s], counts[s] ? best[s] : 0.0, mr,
               (unsigned long long)agree[s], (unsigned long long)self_hits[s], (unsigned long long)counts[s]);
        fprintf(stderr, "embree %s: %s %llu rays, %.2f Mrays/s, agrees with Prism on %llu (%llu more: Embree self-hits)\n",
                RTC_VERSION_STRING, kinds[s], (unsigned long long)counts[s], mr, (unsigned long long)agree[s],
                (unsigned long long)self_hits[s]);
    }
    printf("], \"sink\": %llu}\n", (unsigned long long)(sink & 1));
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    for (int s = 0; s < 3; s++) free(sets[s]);
    free(buf);
    return 0;
}
