/*
 * Dualform: real-time ROI mesh deformation with the dual Laplacian.
 *
 * The public C API. Pure C99; includes only <stddef.h>, <stdint.h> and
 * <stdbool.h>.
 *
 * Conventions
 * - Every fallible call returns a dfm_result. DFM_OK is 0. Out-parameters are
 *   set to NULL/zero on failure.
 * - The message of the last failing call is per thread:
 *   dfm_last_error_message() returns it until the next failing dfm_ call on
 *   the same thread. A successful call does not clear it.
 * - Descriptor structs are valid when zero-initialised ("= {0}"); a zero field
 *   takes the documented default.
 * - Descriptors grow without breaking callers. Each begins with
 *   `struct_size`: set it to sizeof the struct. 0 stands for the struct's
 *   layout in version 0.2, where the field appeared: every field the 0.2.0
 *   header declares is read, and fields a later version adds take their
 *   defaults. The library reads
 *   only struct_size bytes, so a caller built against an older, smaller
 *   struct keeps working and the fields it lacks take their defaults; a
 *   caller built against a newer, larger struct is accepted when the bytes
 *   this library does not know are zero, and refused with
 *   DFM_ERROR_UNSUPPORTED otherwise. Structs embedded in descriptors
 *   (dfm_solver_settings) keep their size and grow into `reserved`, which
 *   must be zero.
 * - Handles are values, not addresses: an index and a generation. A
 *   destroyed handle is refused with DFM_ERROR_INVALID_HANDLE for ever, even
 *   after its memory serves a new object.
 * - dfm_X_destroy(NULL) is a no-op.
 * - Nothing throws across this boundary, and nothing aborts on bad input.
 */
#ifndef DUALFORM_DUALFORM_H
#define DUALFORM_DUALFORM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "dualform/version.h"

/* Marks the library's exported functions: empty for the static library
 * (define DFM_STATIC), default visibility while building the shared one. */
#if defined(DFM_STATIC)
#define DFM_API
#elif defined(DFM_BUILDING_LIBRARY)
#define DFM_API __attribute__((visibility("default")))
#else
#define DFM_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------- results */

typedef enum dfm_result {
    DFM_OK = 0,
    DFM_ERROR_INVALID_ARGUMENT = 1, /* NULL where a value is needed, a bad size or flag */
    DFM_ERROR_NOT_FOUND = 2,        /* a file, model or vertex that does not exist */
    DFM_ERROR_IO = 3,               /* reading or writing a file failed */
    DFM_ERROR_PARSE = 4,            /* a file's contents are malformed */
    DFM_ERROR_OUT_OF_RANGE = 5,     /* an index past the end of its array */
    DFM_ERROR_UNSUPPORTED = 6,      /* valid, but not something Dualform does */
    DFM_ERROR_OUT_OF_MEMORY = 7,    /* an allocation failed; nothing was changed */
    DFM_ERROR_NUMERICAL = 8,        /* non-finite input, or a solve that broke down */
    DFM_ERROR_INVALID_HANDLE = 9,   /* a handle already destroyed, or of the wrong kind */
    DFM_ERROR_BUSY = 10,            /* the object is in use in a way that forbids the call */
    DFM_ERROR_DEVICE = 11,          /* the graphics device failed (renderer only) */
    DFM_ERROR_CANCELLED = 12,       /* the work was cancelled before it finished */
    DFM_ERROR_INTERNAL = 13         /* a defect of Dualform's; the message says where */
} dfm_result;

/* The name of a result code ("DFM_ERROR_PARSE"); never NULL. Thread-safe. */
DFM_API const char* dfm_result_name(dfm_result result);

/* The message of the last failing dfm_ call on this thread ("" if none). The
 * string belongs to the library and stays valid until the next failing call on
 * this thread. Thread-safe (each thread has its own). */
DFM_API const char* dfm_last_error_message(void);

/* The code of the last failing dfm_ call on this thread (DFM_OK if none). */
DFM_API dfm_result dfm_last_error_code(void);

/* DFM_VERSION of the library actually linked (may differ from the header's). Never fails;
 * thread-safe. */
DFM_API uint32_t dfm_version(void);

/* Whether this library can serve a caller compiled against the header of
 * version `header_version`: the same major version and, before 1.0, the same
 * minor one; from 1.0 on, a library minor at least the header's. Hosts check
 * once at start-up with DFM_VERSION_MATCHES(). Never fails; thread-safe. */
DFM_API bool dfm_version_compatible(uint32_t header_version);

/* Whether the library loaded at run time serves this header's version. */
#define DFM_VERSION_MATCHES() dfm_version_compatible(DFM_VERSION)

/* ---------------------------------------------------------------- camera */

/* A pinhole camera: at `eye` looking at `target`, `up`
 * giving the image's up direction, `fov_y_degrees` the full vertical field of
 * view, an image of width x height pixels. Pixel coordinates are continuous:
 * (0,0) is the top-left corner, x right, y down; (w/2,h/2) looks at target.
 * Picking and the renderer use the same camera, so a pixel and a pick agree. */
typedef struct dfm_camera {
    double eye[3];        /* where the camera is */
    double target[3];     /* the point it looks at: seen at pixel (width/2, height/2) */
    double up[3];         /* the image's up direction; not parallel to target - eye */
    double fov_y_degrees; /* the full vertical field of view, between 0 and 180 */
    uint32_t width;       /* the image's width in pixels */
    uint32_t height;      /* the image's height in pixels */
} dfm_camera;

/* ---------------------------------------------------------------- arrays */

typedef enum dfm_scalar_type {
    DFM_SCALAR_FLOAT32 = 0, /* float x, y, z (the default) */
    DFM_SCALAR_FLOAT64 = 1  /* double x, y, z */
} dfm_scalar_type;

/* Host-owned 3-vectors read by the library: `count` vectors, vector i at
 * (const char*)data + i * stride. stride 0 means tightly packed. */
typedef struct dfm_vec3_input {
    const void* data;     /* the first vector's x */
    size_t count;         /* number of vectors */
    size_t stride;        /* bytes from one vector to the next; 0: packed */
    dfm_scalar_type type; /* float (the default) or double components */
} dfm_vec3_input;

/* Host-owned 3-vectors written by the library; same layout rules. The count
 * is the capacity: a call that needs more fails with
 * DFM_ERROR_INVALID_ARGUMENT and writes nothing. */
typedef struct dfm_vec3_output {
    void* data;           /* where the first vector's x goes */
    size_t count;         /* capacity, in vectors */
    size_t stride;        /* bytes from one vector to the next; 0: packed */
    dfm_scalar_type type; /* float (the default) or double components */
} dfm_vec3_output;

/* ---------------------------------------------------------------- context */

typedef struct dfm_context dfm_context;

/* Host memory hooks. They serve exactly: the object behind every handle
 * (context, mesh, ROI, session), the context's and each mesh's state
 * record, and each rest-pose model record (not its arrays). Every array
 * (positions, triangles, adjacency, ROIs, the solver's rows and factor,
 * frames, the pick scene) comes from the C++ global allocator (operator
 * new, plain and aligned, which a host may replace); its failures are
 * reported the same way. While a context lives, the large arrays that
 * destroyed sessions freed are kept for later set-ups (shared by the
 * process's contexts), and freed when the last context and every object
 * made from it are destroyed.
 * alloc returns memory aligned to `alignment` (a power of two up to 64) or
 * NULL on failure, which the call reports as DFM_ERROR_OUT_OF_MEMORY. free
 * receives the size that was allocated. Both hooks may be called from any
 * thread, including the threads that run the context's work, at once, and
 * with locks of the library's held (free runs wherever the last reference
 * to a record goes, a bake or a destroy among them): they must be
 * thread-safe, must not call any dfm_ function nor wait for a thread that
 * does, and must not unwind. They stay in use until the context and every
 * object made from it are destroyed, after dfm_context_destroy too. */
typedef struct dfm_allocator {
    void* (*alloc)(void* user, size_t size, size_t alignment); /* NULL on failure */
    void (*free)(void* user, void* memory, size_t size);       /* size as allocated */
    void* user;                                                /* passed to both */
} dfm_allocator;

/* How much a log message matters. */
typedef enum dfm_log_level {
    DFM_LOG_DEBUG = 0,
    DFM_LOG_INFO = 1,
    DFM_LOG_WARNING = 2,
    DFM_LOG_ERROR = 3
} dfm_log_level;

/* Stable message ids for the log callback, so a host can filter or test. */
typedef enum dfm_log_id {
    DFM_LOG_ID_LOAD_WARNING = 1,        /* a mesh file had a recoverable defect */
    DFM_LOG_ID_WATER_FILL_SUSPECT = 2,  /* Water-Filling most likely leaked */
    DFM_LOG_ID_SOLVE_NOT_CONVERGED = 3, /* a synchronous solve hit its iteration cap */
    DFM_LOG_ID_SOLVE_FAILED = 4,        /* a solve broke down; the last good result is kept */
    DFM_LOG_ID_CORRECTIVE_DAMPED = 5    /* a bake in a pose met ill-conditioned skinning */
} dfm_log_id;

/* Receives diagnostics. Called on the thread that made the dfm_ call (never
 * from the context's work: asynchronous outcomes are in dfm_frame_info),
 * with no lock of the library's held: it may make any call, and wait for
 * threads that do, but destroy the objects that call works on. `message`
 * lives only during the call. */
typedef void (*dfm_log_fn)(void* user, dfm_log_level level, dfm_log_id id, const char* message);

/* Where a context's work runs: its sessions' set-ups and solves, and the
 * solver's parallel loops inside them (sdk/README.md, "Threads"). Results do
 * not depend on it, bit for bit. */
typedef enum dfm_work_mode {
    /* The default: the context starts worker_count threads ("dfm-worker"),
     * shared by all its sessions, and stops them when the context and every
     * object made from it are destroyed. */
    DFM_WORK_POOL = 0,
    /* The host's job system runs the work (dfm_context_desc.job_system);
     * the library starts no thread. */
    DFM_WORK_JOB_SYSTEM = 1,
    /* No thread at all: the work runs on the host's thread inside
     * dfm_context_step and inside the calls that wait for it
     * (dfm_session_wait, dfm_session_solve, dfm_session_set_solver). */
    DFM_WORK_HOST_STEPPED = 2
} dfm_work_mode;

/* One piece of a context's work handed to the host's job system: a
 * session's set-up or solve, or a share of a parallel loop of one. */
typedef struct dfm_job dfm_job;

/* The host's job system (DFM_WORK_JOB_SYSTEM), as Jolt Physics takes one:
 * the library hands jobs over, the host runs them on its workers. At most
 * worker_count of the context's jobs work at once (one that ends may hand
 * over the next just before it returns). A job never waits for a job that
 * has not started, so a host may run them in any order, on any number of
 * threads. */
typedef struct dfm_job_system {
    /* Hands `job` over: the host runs it exactly once, on any thread, with
     * dfm_job_run, after enqueue has returned. Called from any thread: from
     * the calls that queue work (dfm_session_create, submit, bake), from
     * inside jobs, and from a solve's parallel loops (dfm_session_solve's
     * too). No lock is held then that a call takes, other than the calls
     * that wait for the context's work: enqueue may make any call, and wait
     * for threads that do, but dfm_session_wait, cancel, solve, set_solver,
     * bake and destroy on the context's sessions and dfm_context_destroy,
     * which may wait for the very work that is calling it (sdk/README.md,
     * "Threads"). */
    void (*enqueue)(void* user, dfm_job* job);
    void* user; /* passed to enqueue */
} dfm_job_system;

/* How a context is made; zero-initialised, every field takes its default. */
typedef struct dfm_context_desc {
    uint32_t struct_size; /* sizeof(dfm_context_desc); see the conventions */
    /* DFM_VERSION of the header the caller was built with: the context is
     * refused (DFM_ERROR_UNSUPPORTED) unless dfm_version_compatible(). 0:
     * not checked. */
    uint32_t header_version;
    dfm_allocator allocator; /* both hooks NULL: malloc/free */
    dfm_log_fn log;          /* NULL: no logging */
    void* log_user;          /* passed to `log` */
    /* The workers of the context's work, shared by all its sessions; 0
     * means 1, at most 256. DFM_WORK_POOL: the threads the context starts.
     * DFM_WORK_JOB_SYSTEM: how many jobs the host may run at once.
     * DFM_WORK_HOST_STEPPED: 0 or 1 (the host's thread; more is
     * DFM_ERROR_INVALID_ARGUMENT). A solve's
     * parallel loops split their work by it; results do not depend on it,
     * bit for bit. Where a core is free, 2 keeps a 20,000-vertex drag up
     * with a 60 Hz host (docs/benchmarks.md). */
    uint32_t worker_count;
    /* Threads of the Embree device that picking builds (once per mesh, on
     * the first pick or click fill): 1 keeps the build on the calling
     * thread; 0 lets Embree start one per hardware thread (its default,
     * named by Embree). At most 1024. */
    uint32_t pick_thread_count;
    /* The folder in which dfm_mesh_load finds "model:NAME" (as NAME.off;
     * NAME is a plain file name, no folder in it); copied at creation. NULL
     * or "": no folder, and model:NAME is DFM_ERROR_NOT_FOUND. The library
     * reads no environment variable: a host that wants DUALFORM_MODELS reads
     * it and passes it here. */
    const char* models_directory;
    /* Where the files a loaded file refers to may also lie. A glTF
     * document's external buffers (relative URIs) are read only inside the
     * document's own folder: a URI that is absolute, has a scheme (file:,
     * http:) or leads out of the folder through ".." is refused, and the load
     * fails with DFM_ERROR_UNSUPPORTED naming the URI, so that an asset
     * cannot read (and a save then embed) any other file the process can
     * read. A folder named here widens that: URIs may also lead anywhere
     * inside it (still relative, never a scheme). Copied at creation; a
     * relative path is taken from the working folder of each load. NULL or
     * "": the document's folder only. The other formats follow no reference
     * (OBJ's mtllib is skipped). */
    const char* reference_folder;
    /* Where the work runs; 0: DFM_WORK_POOL. A value no dfm_work_mode has
     * is DFM_ERROR_INVALID_ARGUMENT. */
    dfm_work_mode work_mode;
    /* DFM_WORK_JOB_SYSTEM: the host's job system, `enqueue` required
     * (NULL: DFM_ERROR_INVALID_ARGUMENT); all zero in the other modes
     * (anything set: DFM_ERROR_INVALID_ARGUMENT). */
    dfm_job_system job_system;
} dfm_context_desc;

/* Creates a context; desc may be NULL for all defaults. *out receives the
 * context, owned by the caller until dfm_context_destroy. Thread-safe. */
DFM_API dfm_result dfm_context_create(const dfm_context_desc* desc, dfm_context** out);

/* Releases the caller's reference. Objects created from the context keep what
 * they need alive, so destroying it first is safe. NULL is a no-op. Must not
 * race another call on the same context. Not thread-safe for this context.
 * With DFM_WORK_POOL the threads stop once every object made from the
 * context is destroyed too. With DFM_WORK_JOB_SYSTEM and
 * DFM_WORK_HOST_STEPPED it ends the host's part at once: queued work is
 * cancelled (a set-up that had not run ends with DFM_ERROR_CANCELLED, as do
 * waits for queued targets), it waits for every job already handed over
 * (so the host keeps its job system running until it returns, and does not
 * call it from inside a job), and after it returns no job is handed over
 * and none runs. A set-up or solve that a job is running goes on to its
 * end meanwhile and publishes its frame (dfm_session_destroy, by contrast,
 * stops a running solve after its current iteration). Sessions that
 * outlive it refuse dfm_session_submit with DFM_ERROR_CANCELLED; those
 * whose set-up had ended still solve on the caller's thread
 * (dfm_session_solve). dfm_session_create on its meshes then answers
 * DFM_ERROR_CANCELLED: no work of theirs can run. */
DFM_API void dfm_context_destroy(dfm_context* context);

/* Runs a job the host's job system was handed (dfm_job_system.enqueue), on
 * the calling thread: a piece of the work, or nothing when the work is
 * already done. Every job handed over is run exactly once, also while the
 * context is being destroyed. NULL is a no-op. Thread-safe. */
DFM_API void dfm_job_run(dfm_job* job);

/* DFM_WORK_HOST_STEPPED: runs the context's queued work on the calling
 * thread, the sessions' set-ups and solves one after the other in the order
 * they were submitted (a session with newer targets queues again behind
 * the others once its solve ends, so none starves). Once `budget_us`
 * microseconds have passed it starts no further iteration: it returns at
 * most one iteration past the budget (a set-up runs whole). The budget is
 * wall-clock time (a steady clock), not the thread's own: an iteration in
 * progress when it ends runs on, so where the thread waits for a core the
 * step overruns by that iteration's wall time, more than its work. A
 * budget above a day (UINT64_MAX included) is a day. A solve stopped
 * there resumes first at the next step and finishes with the same bits as
 * if it had not stopped; frames are published as with threads (previews,
 * on_frame on this thread). 0: runs until no work is left. *work_left (may
 * be NULL): whether work is still queued. Threads that step one context
 * take turns. DFM_ERROR_UNSUPPORTED for a context in another mode. */
DFM_API dfm_result dfm_context_step(dfm_context* context, uint64_t budget_us, bool* work_left);

/* ---------------------------------------------------------------- mesh */

typedef struct dfm_mesh dfm_mesh;

/* How dfm_mesh_create joins a host's split copies of a vertex (the copies a
 * renderer keeps for UV, normal or material seams) into one surface vertex. */
typedef enum dfm_weld_mode {
    DFM_WELD_NONE = 0,     /* the default: every host vertex is a surface vertex */
    DFM_WELD_EXACT = 1,    /* copies at bit-identical positions */
    DFM_WELD_TOLERANCE = 2 /* copies within weld_tolerance of each other */
} dfm_weld_mode;

/* The integer type of a host's joint indices (dfm_skin_input). */
typedef enum dfm_index_type {
    DFM_INDEX_UINT32 = 0, /* the default */
    DFM_INDEX_UINT16 = 1,
    DFM_INDEX_UINT8 = 2
} dfm_index_type;

/* The most joints a skin may have. */
#define DFM_MAX_JOINTS 65536u
/* The most influences (joints and weights) a vertex may have. */
#define DFM_MAX_INFLUENCES 32u

/* A host's linear blend skin for dfm_mesh_create (dfm_mesh_desc.skin), as
 * glTF and engines define it: with J_j joint j's world matrix at a pose
 * (dfm_mesh_set_pose_joints), host vertex v is shown at
 *
 *     sum_k w_vk * J[j_vk] * inverse_bind[j_vk] * p_v
 *
 * where p_v is its position as created (the bind space). Weights must be
 * finite and not negative, and are normalised to sum 1 (a vertex whose
 * weights sum to 0 is refused); a zero weight's joint is ignored, but every
 * joint index must be below joint_count. Errors name the vertex and slot. */
typedef struct dfm_skin_input {
    uint32_t joint_count; /* joints, at most DFM_MAX_JOINTS; 0: no skin (the rest ignored) */
    /* joint_count column-major 4x4 affine matrices: each joint's inverse
     * bind matrix (the inverse of its world matrix in the bind pose). */
    const double* inverse_bind_matrices;
    uint32_t influence_count; /* joints and weights per vertex, 1 to DFM_MAX_INFLUENCES */
    /* Vertex v's influence_count joint indices, at (const char*)joints + v *
     * joint_stride, of joint_type. */
    const void* joints;
    size_t joint_stride;       /* bytes from one vertex's joints to the next; 0: packed */
    dfm_index_type joint_type; /* 0: uint32_t */
    /* Vertex v's influence_count weights, at (const char*)weights + v *
     * weight_stride, of weight_type. */
    const void* weights;
    size_t weight_stride;        /* bytes from one vertex's weights to the next; 0: packed */
    dfm_scalar_type weight_type; /* 0: float */
} dfm_skin_input;

/* A triangle mesh from the host's arrays, copied (the host may free its
 * arrays after the call). Indices: triangle t's corners are the three
 * uint32_t at (const char*)indices + t * index_stride (0: packed, 12 bytes).
 *
 * Host numbering: with a weld, the host's vertices stay the host's. Copies
 * at one position are joined only where faces around it connect them (two
 * faces using them share an edge whose two ends are at equal positions), so
 * two sheets that merely touch at a point stay apart. Picking, ROIs and the
 * solver work on the surface vertices; every vertex index the API takes may
 * name any copy and means its surface vertex; every vertex index it returns
 * (dfm_roi_read, dfm_hit.vertex, the frame view's lists) is the lowest host
 * index of that surface vertex; positions and normals (mesh and session
 * reads) come in the host's order and count, each copy with its surface
 * vertex's value. dfm_mesh_read_surface_map gives every copy's lowest copy.
 * Files from glTF are numbered the same way (their vertices are the host's),
 * and files from FBX by their control points (the file's own vertices, before
 * any split for UVs or normals). */
typedef struct dfm_mesh_desc {
    uint32_t struct_size;     /* sizeof(dfm_mesh_desc); see the conventions */
    dfm_vec3_input positions; /* the vertices */
    const uint32_t* indices;  /* three vertex indices per triangle */
    size_t triangle_count;    /* number of triangles */
    size_t index_stride;      /* bytes from one triangle's indices to the next; 0: 12 */
    dfm_weld_mode weld;       /* split copies joined how; 0: DFM_WELD_NONE */
    /* DFM_WELD_TOLERANCE: the largest distance between two copies, as a
     * fraction of the bounding-box diagonal; must be positive and finite. */
    double weld_tolerance;
    /* The host's skin (joints, weights, inverse bind matrices); zero: the
     * mesh has none. Copies are welded only where their skins agree. */
    dfm_skin_input skin;
} dfm_mesh_desc;

/* Copies a mesh from host arrays. Errors: NULL arguments, no vertices or
 * triangles, an index out of range (the message names triangle and corner),
 * a non-finite position (names the vertex). A triangle repeating a vertex is
 * dropped with a DFM_LOG_ID_LOAD_WARNING, as the file loaders drop it; the
 * mesh's triangles (dfm_mesh_read_indices, dfm_hit.face) are then the kept
 * ones, in order. *out is owned by the caller. Thread-safe. */
DFM_API dfm_result dfm_mesh_create(dfm_context* context, const dfm_mesh_desc* desc, dfm_mesh** out);

/* Loads an OFF, OBJ, PLY, glTF 2.0 (.gltf with embedded or external
 * buffers, .glb) or FBX 7.x file (.fbx, binary or ASCII, where the library
 * was built with Assimp: DFM_ERROR_UNSUPPORTED otherwise), or "model:NAME":
 * NAME.off in the context's models_directory (dfm_context_desc). glTF: every
 * triangle primitive of the default scene, node transforms applied (world
 * space), or of one mesh with "FILE.glb#mesh=NAME" (or its index), in its
 * own space; split copies are welded exactly and numbered as the file has
 * them (see dfm_mesh_desc). FBX: every mesh the scene instances, in metres
 * with +Y up (the file's units and axes applied), numbered by control point,
 * with its skin, animation stacks and blend shapes (docs/fbx.md).
 * Unsupported data (Draco, quantized positions) is refused naming the mesh,
 * primitive and accessor; external buffers are read only inside the file's
 * folder (see dfm_context_desc.reference_folder). Errors name the file,
 * line or byte offset and element. Recoverable defects go to the log
 * (DFM_LOG_ID_LOAD_WARNING). *out is owned by the caller. Thread-safe. */
DFM_API dfm_result dfm_mesh_load(dfm_context* context, const char* path, dfm_mesh** out);

/* Writes the mesh's current rest pose (after bakes) to an .off, .obj, .ply,
 * .gltf, .glb or .fbx file, atomically: a failed save leaves an existing file
 * untouched. OFF, OBJ and PLY get the welded surface. glTF gets the host's
 * vertices: a mesh loaded from glTF is written back into its asset with the
 * new positions, POSITION bounds, normals and tangents of the moved part,
 * everything else kept (docs/gltf.md); another mesh gets a fresh minimal
 * asset. FBX is written only for a mesh loaded from a binary FBX file, back
 * into that file: new control points and normals where the edit moved them,
 * every other node as it was (docs/fbx.md); DFM_ERROR_UNSUPPORTED for any
 * other mesh. Thread-safe. */
DFM_API dfm_result dfm_mesh_save(const dfm_mesh* mesh, const char* path);

/* Releases the caller's reference; sessions on the mesh keep it alive. NULL is
 * a no-op. Must not race another call on the same mesh. Not thread-safe for this mesh. */
DFM_API void dfm_mesh_destroy(dfm_mesh* mesh);

/* A mesh's figures (dfm_mesh_get_info). */
typedef struct dfm_mesh_info {
    size_t vertex_count;         /* the host's vertices (split copies counted): what reads fill */
    size_t triangle_count;       /* the host's triangles, as dfm_mesh_read_indices gives them */
    double bounds_min[3];        /* the axis-aligned bounding box's lowest corner */
    double bounds_max[3];        /* and its highest */
    double diagonal;             /* of the bounding box: the unit of tolerances */
    size_t components;           /* connected components */
    size_t boundary_edges;       /* edges with one face */
    size_t bake_count;           /* bakes that undo can still take back */
    size_t redo_count;           /* undone bakes that redo can bring back */
    size_t surface_vertex_count; /* vertices after the weld; vertex_count without one */
} dfm_mesh_info;

/* Fills *out with the current rest pose's figures. Thread-safe. */
DFM_API dfm_result dfm_mesh_get_info(const dfm_mesh* mesh, dfm_mesh_info* out);

/* A mesh's working memory in bytes, by part (dfm_mesh_get_memory): the
 * capacities of the arrays Dualform holds for it, exactly. Sessions on the
 * mesh report their own (dfm_session_get_memory). */
typedef struct dfm_mesh_memory {
    size_t rest_pose; /* the current rest pose's positions and triangles */
    size_t adjacency; /* its edges, face and vertex neighbours, faces per vertex */
    size_t model;     /* its dual Laplacian (neighbours, weights, heights) */
    /* The earlier and undone rest poses that undo and redo can bring back,
     * each counted in full (all three parts above). */
    size_t history;
    /* The pick scene once a pick has built it, else 0: its copy of the
     * positions and triangles and the vertex and index buffers handed to
     * Embree. Embree's BVH is not counted (Embree does not report it). */
    size_t pick_scene;
    size_t total; /* the sum of the parts above */
} dfm_mesh_memory;

/* Fills *out with the mesh's working memory. Thread-safe. */
DFM_API dfm_result dfm_mesh_get_memory(const dfm_mesh* mesh, dfm_mesh_memory* out);

/* Copies the rest positions (all vertex_count of them) into the host's
 * buffer. Thread-safe. */
DFM_API dfm_result dfm_mesh_read_positions(const dfm_mesh* mesh, const dfm_vec3_output* out);

/* Copies the triangles' vertex indices (3 per triangle) into `indices`,
 * which holds `capacity` uint32_t: the host's triangles in the host's
 * numbering. Thread-safe. */
DFM_API dfm_result dfm_mesh_read_indices(const dfm_mesh* mesh, uint32_t* indices, size_t capacity);

/* For each host vertex (vertex_count of them), the lowest host index of its
 * surface vertex: the index the API returns for it, shared by all its split
 * copies (each vertex's own index on a mesh without a weld). `capacity` is
 * in entries. Thread-safe. */
DFM_API dfm_result dfm_mesh_read_surface_map(const dfm_mesh* mesh, uint32_t* lowest_copy,
                                             size_t capacity);

/* Area-weighted unit vertex normals of the rest pose. Thread-safe. */
DFM_API dfm_result dfm_mesh_read_normals(const dfm_mesh* mesh, const dfm_vec3_output* out);

/* The same as dfm_mesh_read_indices in 16 bits, for meshes of at most 65,536
 * vertices (DFM_ERROR_OUT_OF_RANGE otherwise, writing nothing). Thread-safe. */
DFM_API dfm_result dfm_mesh_read_indices16(const dfm_mesh* mesh, uint16_t* indices,
                                           size_t capacity);

/* Replaces the rest pose with the host's positions (vertex_count of them;
 * the triangles stay; of split copies the lowest one's position is taken), as a new step of the
 * bake history: undo brings the previous pose back, and what could be redone is forgotten. Sessions
 * created before keep editing the shape they started from and can no longer
 * bake (DFM_ERROR_BUSY, as after another session's bake): create new ones.
 * A non-finite position is DFM_ERROR_NUMERICAL (the message names the
 * vertex) and changes nothing. Thread-safe. */
DFM_API dfm_result dfm_mesh_set_positions(dfm_mesh* mesh, const dfm_vec3_input* positions);

/* Takes back the last bake: the rest pose before it returns. Sessions created
 * before keep working on the shape they started from, but can no longer
 * bake. DFM_ERROR_NOT_FOUND when there is nothing to undo. Thread-safe. */
DFM_API dfm_result dfm_mesh_undo_bake(dfm_mesh* mesh);

/* Brings back the last undone bake. DFM_ERROR_NOT_FOUND when there is none;
 * a new bake forgets what could be redone. Thread-safe. */
DFM_API dfm_result dfm_mesh_redo_bake(dfm_mesh* mesh);

/* ---------------------------------------------------------------- skin and pose */

/* A skinned mesh (a glTF or FBX asset's skins, animations and morph targets, or a
 * host's dfm_skin_input) can be posed: then everything that reads or edits
 * the rest pose sees it posed, as the engine shows it (morph targets apply
 * before skinning): dfm_mesh_read_positions and _normals, dfm_mesh_get_info,
 * picking, Water-Filling and the other ROIs, sessions (their rest shape,
 * handle targets, frames), dfm_mesh_set_positions and the renderer. A bake
 * in a pose keeps the edit as its exact bind-space corrective: each moved
 * vertex's bind position moves by d = L_v^-1 D', D' its posed displacement
 * and L_v the 3x3 part of sum_k w_vk J[j_vk] inverse_bind[j_vk], so that
 * skinning the bind shape at that pose gives the edited shape (to rounding);
 * where L_v is ill-conditioned (it shrinks a direction below a thousandth
 * of the larger of 1 and its largest singular value: cancelling weights, a
 * collapsed joint) a damped inverse is used and the bake logs
 * DFM_LOG_ID_CORRECTIVE_DAMPED naming the vertices. The bake history is in
 * bind space; undo and redo show it at the current pose. A save writes the
 * bind space into a glTF or FBX asset (its positions, or the corrective as a morph
 * target, docs/skinning.md); OFF, OBJ and PLY get the shown, posed surface.
 * Setting or clearing a pose changes the shown rest pose, so sessions made
 * before can no longer bake (DFM_ERROR_BUSY), as after another bake. */

/* What poses a mesh (dfm_mesh_get_skin_info). */
typedef struct dfm_skin_info {
    uint32_t joint_count;        /* joints of every skin; 0 without a skin */
    uint32_t max_influences;     /* the most joints one vertex has */
    size_t skinned_vertex_count; /* host vertices with influences */
    uint32_t animation_count;    /* the file's animations (glTF, FBX) */
    uint32_t morph_target_count; /* morph targets of the loaded meshes */
    bool posed;                  /* a pose is set */
    int32_t pose_animation;      /* the pose's animation, or -1: joint matrices, or none */
    double pose_time;            /* the pose's time in seconds, as clamped */
    /* The last bake (or dfm_mesh_set_positions) in a pose (all 0 before
     * one): the vertices it moved, */
    size_t corrective_vertex_count;
    double corrective_worst_condition; /* the largest condition number of their L_v, */
    size_t corrective_damped_count;    /* and how many took the damped inverse */
} dfm_skin_info;

/* Fills *out. A mesh without a skin or morph targets has all zeros and
 * pose_animation -1. Thread-safe. */
DFM_API dfm_result dfm_mesh_get_skin_info(const dfm_mesh* mesh, dfm_skin_info* out);

/* One joint (dfm_mesh_get_joint_info). */
typedef struct dfm_joint_info {
    const char* name; /* the joint's node name; lives as long as the mesh */
    uint32_t parent;  /* the nearest ancestor that is a joint, UINT32_MAX for none */
} dfm_joint_info;

/* Fills *out for joint `joint`; DFM_ERROR_OUT_OF_RANGE past the last.
 * Thread-safe. */
DFM_API dfm_result dfm_mesh_get_joint_info(const dfm_mesh* mesh, uint32_t joint,
                                           dfm_joint_info* out);

/* One animation of the file (dfm_mesh_get_animation_info). */
typedef struct dfm_animation_info {
    const char* name;              /* its name, or "animation_N"; lives as long as the mesh */
    double start;                  /* its first key, in seconds */
    double end;                    /* its last key, in seconds */
    uint32_t translation_channels; /* channels that animate a node's translation */
    uint32_t rotation_channels;    /* a node's rotation */
    uint32_t scale_channels;       /* a node's scale */
    uint32_t weight_channels;      /* morph target weights */
} dfm_animation_info;

/* Fills *out for animation `animation`; DFM_ERROR_OUT_OF_RANGE past the
 * last. Thread-safe. */
DFM_API dfm_result dfm_mesh_get_animation_info(const dfm_mesh* mesh, uint32_t animation,
                                               dfm_animation_info* out);

/* The index of the first animation called `name`; DFM_ERROR_NOT_FOUND
 * (naming the animations there are) when none is. Thread-safe. */
DFM_API dfm_result dfm_mesh_find_animation(const dfm_mesh* mesh, const char* name,
                                           uint32_t* animation);

/* One morph target (dfm_mesh_get_morph_target_info). */
typedef struct dfm_morph_target_info {
    const char* name; /* from mesh.extras.targetNames, or "target_N"; lives as long as the mesh */
    double default_weight; /* its node's or mesh's default weight */
    size_t vertex_count;   /* surface vertices it moves */
} dfm_morph_target_info;

/* Fills *out for morph target `target`; DFM_ERROR_OUT_OF_RANGE past the
 * last. Thread-safe. */
DFM_API dfm_result dfm_mesh_get_morph_target_info(const dfm_mesh* mesh, uint32_t target,
                                                  dfm_morph_target_info* out);

/* Poses the mesh at animation `animation` at `time_seconds`, clamped to the
 * animation's first and last key: every node at its rest transform but
 * where a channel animates it (LINEAR, STEP, CUBICSPLINE), morph weights
 * from its weights channels or their defaults. DFM_ERROR_OUT_OF_RANGE for
 * an animation the mesh does not have, DFM_ERROR_NUMERICAL for a time that
 * is not finite, DFM_ERROR_UNSUPPORTED for a mesh without a skin or morph
 * targets. Takes well under a millisecond at 20,000 vertices
 * (docs/benchmarks.md), and dfm_mesh_read_positions after it reads the
 * positions it skinned; the posed model that edits need is built when one
 * first needs it. Thread-safe. */
DFM_API dfm_result dfm_mesh_set_pose_animation(dfm_mesh* mesh, uint32_t animation,
                                               double time_seconds);

/* Poses the mesh from the host's joint matrices, what an engine has each
 * frame: joint_count column-major 4x4 affine world matrices J_j (the
 * library multiplies each by its joint's inverse bind matrix), and
 * morph_weight_count morph target weights (NULL and 0: their defaults).
 * Counts must match the skin's (DFM_ERROR_INVALID_ARGUMENT); a matrix or
 * weight that is not finite, or a matrix whose last row is not 0 0 0 1, is
 * DFM_ERROR_NUMERICAL naming it; nothing changes on an error. Thread-safe. */
DFM_API dfm_result dfm_mesh_set_pose_joints(dfm_mesh* mesh, const double* joint_matrices,
                                            size_t joint_count, const double* morph_weights,
                                            size_t morph_weight_count);

/* Back to the bind space: the rest pose shows unposed again. Thread-safe. */
DFM_API dfm_result dfm_mesh_clear_pose(dfm_mesh* mesh);

/* The pose's joint world matrices J_j, 16 doubles per joint, column-major,
 * into `matrices` (room for `capacity` doubles): those of the pose set, or
 * of the file's nodes at rest when none is. Thread-safe. */
DFM_API dfm_result dfm_mesh_read_joint_matrices(const dfm_mesh* mesh, double* matrices,
                                                size_t capacity);

/* The bind-space rest positions (vertex_count of them, the host's order),
 * after the bakes: on a posed mesh what a save writes, and with the
 * positions as loaded or created, the corrective (their difference). Equal
 * to dfm_mesh_read_positions on a mesh that is not posed. Thread-safe. */
DFM_API dfm_result dfm_mesh_read_bind_positions(const dfm_mesh* mesh, const dfm_vec3_output* out);

/* ---------------------------------------------------------------- picking */

/* What a pick found (dfm_mesh_pick, dfm_mesh_pick_ray). */
typedef struct dfm_hit {
    bool hit;              /* false: the ray missed, and nothing else is set */
    uint32_t face;         /* the triangle hit */
    uint32_t vertex;       /* the face's corner nearest the hit point */
    double point[3];       /* where */
    double distance;       /* along the ray */
    double barycentric[3]; /* of the point in the face, one weight per corner */
} dfm_hit;

/* Casts the ray through pixel (x, y) of the camera onto the rest pose (Embree;
 * the scene is built on first use and after each bake). A miss is DFM_OK with
 * out->hit false. Thread-safe. */
DFM_API dfm_result dfm_mesh_pick(dfm_mesh* mesh, const dfm_camera* camera, double x, double y,
                                 dfm_hit* out);

/* The same along a ray given by origin and direction (not necessarily unit). Errors and thread
 * safety as dfm_mesh_pick; `out` is the caller's. */
DFM_API dfm_result dfm_mesh_pick_ray(dfm_mesh* mesh, const double origin[3],
                                     const double direction[3], dfm_hit* out);

/* ---------------------------------------------------------------- ROI */

/* A region of interest: a set of vertices of one mesh, immutable. */
typedef struct dfm_roi dfm_roi;

/* How a Water-Filling went: the cut loops that bound the region. */
typedef struct dfm_water_fill_diagnosis {
    size_t loops;              /* cut loops bounding the region */
    bool bounded_by_last_loop; /* the loop through `last` is one of them */
    bool suspect;              /* most likely leaked past the intended limb */
} dfm_water_fill_diagnosis;

/* The paper's Water-Filling from vertex `first` up to the cutting plane through
 * vertex `last` whose normal is the direction from `first` to `last`.
 * `diagnosis` may be NULL. A suspect region is still returned (and logged as
 * DFM_LOG_ID_WATER_FILL_SUSPECT): the host decides. *out is owned by the
 * caller. Thread-safe. */
DFM_API dfm_result dfm_roi_water_fill(dfm_mesh* mesh, uint32_t first, uint32_t last, dfm_roi** out,
                                      dfm_water_fill_diagnosis* diagnosis);

/* Water-Filling from two clicks: each pixel is picked through the camera and
 * its nearest corner vertex used. DFM_ERROR_NOT_FOUND when a click misses
 * the mesh (the message says which). Ownership and thread safety as dfm_roi_water_fill. */
DFM_API dfm_result dfm_roi_water_fill_clicks(dfm_mesh* mesh, const dfm_camera* camera,
                                             const double first_pixel[2],
                                             const double last_pixel[2], dfm_roi** out,
                                             dfm_water_fill_diagnosis* diagnosis);

/* ROI calls below: *out is a new ROI owned by the caller (free it with
 * dfm_roi_destroy), NULL on failure; inputs stay the caller's. All are
 * thread-safe: ROIs are immutable. */

/* An explicit list (duplicates merged). Errors name the offending entry. */
DFM_API dfm_result dfm_roi_from_vertices(dfm_mesh* mesh, const uint32_t* vertices, size_t count,
                                         dfm_roi** out);

/* Every vertex reachable from `center` along edges without leaving the ball
 * of radius `radius` x diagonal around it. */
DFM_API dfm_result dfm_roi_ball(dfm_mesh* mesh, uint32_t center, double radius, dfm_roi** out);

/* The whole mesh. */
DFM_API dfm_result dfm_roi_all(dfm_mesh* mesh, dfm_roi** out);

/* Grows (rings > 0) or shrinks (rings < 0) the region by whole edge rings. */
DFM_API dfm_result dfm_roi_grow(const dfm_roi* roi, int rings, dfm_roi** out);

/* The union of two ROIs of the same mesh. */
DFM_API dfm_result dfm_roi_union(const dfm_roi* a, const dfm_roi* b, dfm_roi** out);

/* The vertices of `a` that are not in `b` (two ROIs of the same mesh). */
DFM_API dfm_result dfm_roi_difference(const dfm_roi* a, const dfm_roi* b, dfm_roi** out);

/* The region's vertices with a neighbour outside it: what stays fixed. */
DFM_API dfm_result dfm_roi_boundary(const dfm_roi* roi, dfm_roi** out);

/* Number of vertices in the region. */
DFM_API dfm_result dfm_roi_count(const dfm_roi* roi, size_t* out);

/* Copies the ascending vertex indices into `vertices` (capacity entries). */
DFM_API dfm_result dfm_roi_read(const dfm_roi* roi, uint32_t* vertices, size_t capacity);

/* NULL is a no-op. ROIs are immutable: every call but destroy is thread-safe. */
DFM_API void dfm_roi_destroy(dfm_roi* roi);

/* ---------------------------------------------------------------- session */

/* Thread safety of session calls: set_group_transform, set_targets, submit,
 * poll, wait, the reads, acquire/release_frame and cancel may be called from
 * any threads at once (staging is under a lock that a solve never holds;
 * reads never wait for a solve). set_solver and bake must not run at the
 * same time as other calls on the same session, nor may any call race
 * destroy. Results land only in the caller's out-parameters. */

typedef struct dfm_session dfm_session;

/* The outer iteration (docs/method.md). Fixed when the session is created. */
typedef enum dfm_method {
    DFM_METHOD_DEFAULT = 0,          /* DFM_METHOD_FITTED_ROTATIONS */
    DFM_METHOD_FITTED_ROTATIONS = 1, /* rotations fitted per dual 1-ring, rigidity rows:
                                        converges, large bends do not fold */
    DFM_METHOD_PAPER = 2             /* Au et al.: l_f = -h_f n_f from each new dual 1-ring */
} dfm_method;

/* What preconditions the conjugate gradients of each linear solve. Fixed
 * when the session is created. The result is the same to the solver's
 * tolerance; the set-up and the cost of a solve differ. */
typedef enum dfm_preconditioner {
    DFM_PRECONDITIONER_DEFAULT = 0,             /* DFM_PRECONDITIONER_CHOLESKY */
    DFM_PRECONDITIONER_CHOLESKY = 1,            /* an exact sparse factor: a slow set-up, a
                                                   solve in one or two steps */
    DFM_PRECONDITIONER_INCOMPLETE_CHOLESKY = 2, /* a factor without fill: quick to set up */
    DFM_PRECONDITIONER_JACOBI = 3               /* the diagonal alone */
} dfm_preconditioner;

/* Zero means the default. Later settings take `reserved` words, which must
 * be zero (DFM_ERROR_UNSUPPORTED otherwise); the struct keeps its size. */
typedef struct dfm_solver_settings {
    double tolerance;                  /* largest vertex update / diagonal that ends it; 1e-5 */
    uint32_t max_iterations;           /* 100 */
    double handle_weight;              /* weight of the soft handle rows; 1 */
    bool hard_handles;                 /* handles met exactly instead of weighted */
    dfm_method method;                 /* DFM_METHOD_FITTED_ROTATIONS */
    dfm_preconditioner preconditioner; /* DFM_PRECONDITIONER_CHOLESKY */
    /* Off (the default), a frame whose targets moved on from the last two
     * solved frames starts from the extrapolation of their shapes; on, from
     * the last shape. Either way it runs to the tolerance. Fixed when the
     * session is created. */
    bool disable_prediction;
    uint32_t reserved[5]; /* zero */
} dfm_solver_settings;

/* A group of handle vertices that move together (one transform). */
typedef struct dfm_handle_group {
    const uint32_t* vertices; /* ROI vertices; copied at session creation */
    size_t count;             /* at least one */
} dfm_handle_group;

/* What a frame is (defined below). */
typedef struct dfm_frame_info dfm_frame_info;

/* Called on the thread that published a frame (the thread running the
 * context's work: a worker, a host job, the stepping thread; the caller's
 * thread for dfm_session_solve), after it is published and before the next
 * one can be: partial, finished and set-up frames alike. `info` lives only
 * during the call. No lock is held then that a call takes, other than the
 * calls that wait for the context's work: the callback may poll, read,
 * acquire and release frames, submit, make any call on other objects, and
 * wait for threads that do, but not dfm_session_wait, cancel, solve,
 * set_solver, bake or destroy on the context's sessions, nor
 * dfm_context_step or dfm_context_destroy (they may wait for the work that
 * is running the callback). It must not throw. A dfm_session_destroy may
 * begin while the callback runs: it waits for the callback, whose calls on
 * the session meanwhile may answer DFM_ERROR_INVALID_HANDLE. Keep it short:
 * that thread does no other work while it runs. */
typedef void (*dfm_frame_ready_fn)(void* user, dfm_session* session, const dfm_frame_info* info);

/* One edit: the region, its handle groups and the solver's settings. */
typedef struct dfm_session_desc {
    uint32_t struct_size;           /* sizeof(dfm_session_desc); see the conventions */
    const dfm_roi* roi;             /* required; created on the same mesh */
    const dfm_handle_group* groups; /* group_count groups; group g is transform g */
    size_t group_count;             /* at least one */
    dfm_solver_settings solver;     /* zero fields: the defaults */
    dfm_frame_ready_fn on_frame;    /* NULL: none */
    void* on_frame_user;            /* passed to on_frame */
} dfm_session_desc;

/* Starts one edit and returns at once: the handle groups are checked here
 * (handle vertices must lie in the ROI, each once, in one group; errors name
 * the group and vertex), then the set-up (assembly, ordering, factorization)
 * is queued as the context's work (dfm_work_mode). Until it ends, frames show the
 * rest pose with `preparing` set, submitted targets wait for it, and cancel
 * and destroy work as usual (destroy stops the set-up part way: between its
 * phases and between the factorization's supernodes; on_frame then hears
 * one last frame with status DFM_ERROR_CANCELLED). A set-up
 * that fails (out of memory, a singular system) is reported in the next
 * frame's status and by every later submit. The session starts at the rest
 * pose with every group's transform the identity. It holds its mesh alive.
 * DFM_ERROR_CANCELLED when the mesh's context, made with
 * DFM_WORK_JOB_SYSTEM or DFM_WORK_HOST_STEPPED, was destroyed (no work of
 * the session could run). *out is owned by the caller. Thread-safe. */
DFM_API dfm_result dfm_session_create(dfm_mesh* mesh, const dfm_session_desc* desc,
                                      dfm_session** out);

/* Takes the session's work out of the context's line, stops its running
 * solve after the current iteration or its set-up part way (see
 * dfm_session_create), waits for that and frees the session; returns within
 * one iteration's time, or one phase's of a running set-up. NULL is a
 * no-op. Must not race another call on the same session. */
DFM_API void dfm_session_destroy(dfm_session* session);

/* Stages group `group`'s transform: a column-major 4x4 affine matrix applied
 * to the group's rest positions (translation in elements 12..14; the bottom
 * row, elements 3, 7, 11 and 15, must be 0 0 0 1: DFM_ERROR_INVALID_ARGUMENT
 * otherwise). Takes effect at the next submit or solve. Never blocks on a
 * solve. DFM_ERROR_OUT_OF_RANGE for a group past the last;
 * DFM_ERROR_NUMERICAL for a matrix element that is not finite, or a finite
 * matrix that takes a handle's target beyond the finite numbers (the
 * message names the group and vertex); nothing is staged then. */
DFM_API dfm_result dfm_session_set_group_transform(dfm_session* session, uint32_t group,
                                                   const double matrix[16]);

/* Stages explicit targets, one per handle vertex in group order (see
 * dfm_session_get_handle_count); replaces the group transforms' targets.
 * DFM_ERROR_INVALID_ARGUMENT for another count, DFM_ERROR_NUMERICAL for a
 * target that is not finite; nothing is staged then. Staged targets are
 * always finite. */
DFM_API dfm_result dfm_session_set_targets(dfm_session* session, const dfm_vec3_input* targets);

/* Number of handle vertices (targets) of the session. */
DFM_API dfm_result dfm_session_get_handle_count(const dfm_session* session, size_t* out);

/* A session's working memory in bytes, by part (dfm_session_get_memory):
 * the capacities of the arrays the session holds, exactly, as measured
 * when its newest frame was published. The mesh it edits is not counted
 * (dfm_mesh_get_memory). */
typedef struct dfm_session_memory {
    /* The complete factor L of the normal matrix: its values, indices,
     * ordering and analysis (with the default preconditioner; the chosen
     * preconditioner's arrays otherwise). The factorization's scratch is
     * not counted: it returns to the library's buffer pool when the
     * factorization ends. */
    size_t factor;
    /* The normal matrix N, the rows it is assembled from (with the fitted
     * rotations, only their faces once the set-up ends), the rigidity
     * rows' rest data and the map of unknowns. */
    size_t normal_matrix;
    /* The iteration's vectors: positions, targets, right-hand sides,
     * Anderson's history, the frame prediction, the Krylov workspace. */
    size_t iteration;
    /* The published frames' slots (positions and normals in double and
     * float) and what the normals are computed from. */
    size_t frames;
    /* The staged, queued and solving targets, the handles' rest positions,
     * the ROI and groups, the whole-mesh rest normals once read. */
    size_t staging;
    size_t total; /* the sum of the parts above */
} dfm_session_memory;

/* Fills *out with the session's working memory. While the set-up runs, the
 * parts it builds (factor, normal_matrix, iteration) are 0: they exist only
 * once it ends. Never blocks on a solve; thread safety as the reads. */
DFM_API dfm_result dfm_session_get_memory(dfm_session* session, dfm_session_memory* out);

/* Changes the tolerance and iteration cap for later solves. handle_weight,
 * hard_handles, preconditioner and disable_prediction are fixed at creation
 * (a different value is DFM_ERROR_UNSUPPORTED); zero fields keep their
 * current values. */
DFM_API dfm_result dfm_session_set_solver(dfm_session* session,
                                          const dfm_solver_settings* settings);

/* Queues the staged targets as the context's work and returns at once with
 * their generation (1, 2, ...). Latest wins: queued targets not yet started
 * are replaced and never solved; the session keeps its place in the
 * context's line, and one whose solve is running queues again behind the
 * others once it ends. A running solve goes on to convergence, so every
 * finished frame is a converged (or iteration-capped) result; while it runs,
 * its iterate is published as a partial frame at most every 8 ms, so the
 * shape follows a fast drag (staging refused targets that are not finite).
 * DFM_ERROR_CANCELLED after dfm_context_destroy with the host's job system
 * or stepping. */
DFM_API dfm_result dfm_session_submit(dfm_session* session, uint64_t* generation);

/* Solves the staged targets on the calling thread (stopping the session's
 * running solve first) and publishes the frame; the result is bit for bit
 * what the context's work would compute from the same state. Its parallel
 * loops take idle workers of the context. For tools and tests. */
DFM_API dfm_result dfm_session_solve(dfm_session* session, uint64_t* generation);

/* Drops queued targets and stops the running solve after its current
 * iteration; returns when no solve of the session runs. Published frames
 * stay. */
DFM_API dfm_result dfm_session_cancel(dfm_session* session);

/* What a frame is. */
struct dfm_frame_info {
    uint64_t generation; /* the targets' generation; 0 = the start state */
    dfm_result status;   /* DFM_ERROR_NUMERICAL: broke down, last good positions */
    bool converged;      /* the tolerance was met before the iteration cap */
    bool partial;        /* stopped early for newer targets */
    uint32_t iterations; /* of the outer iteration */
    double last_update;  /* largest vertex move of the last iteration / diagonal */
    double solve_ms;     /* time spent solving, in milliseconds (a solve that
                            dfm_context_step stopped counts its runs only) */
    /* FNV-1a over the frame's ROI positions as 64-bit words: h starts at
     * 14695981039346656037 and, for each double's bits w (x, y, z of each
     * ROI vertex in order), becomes (h ^ w) * 1099511628211 mod 2^64. */
    uint64_t checksum;
    bool preparing; /* the set-up still runs: the rest pose, nothing solved yet */
};

/* The newest published frame's info, and whether it is newer than
 * `known_generation`: the host's cheap per-frame check. Never blocks on a
 * solve. `is_new` may be NULL. */
DFM_API dfm_result dfm_session_poll(dfm_session* session, uint64_t known_generation,
                                    dfm_frame_info* out, bool* is_new);

/* Waits (no spinning) until the set-up has ended and a finished frame of
 * generation >= `generation` is published: DFM_OK. Generation 0 (or, after a
 * bake, the baked frame's) waits for the set-up alone: DFM_OK once the
 * frame that ends it is published, so the newest frame (`out`, poll) no
 * longer says `preparing`. DFM_ERROR_CANCELLED if that generation was
 * cancelled, DFM_ERROR_BUSY on timeout (timeout_ms < 0: no limit; 0 polls).
 * `out` may be NULL. */
DFM_API dfm_result dfm_session_wait(dfm_session* session, uint64_t generation, int64_t timeout_ms,
                                    dfm_frame_info* out);

/* Copies the newest frame's positions of the whole mesh into the host's
 * buffer (vertex_count entries), and its info into `info` (may be NULL). Never
 * returns a torn frame; a solve never waits for it. */
DFM_API dfm_result dfm_session_read_positions(dfm_session* session, const dfm_vec3_output* out,
                                              dfm_frame_info* info);

/* The same as unit vertex normals of the whole mesh. */
DFM_API dfm_result dfm_session_read_normals(dfm_session* session, const dfm_vec3_output* out,
                                            dfm_frame_info* info);

/* Only the ROI's vertices, in the ascending order of dfm_roi_read: the cheap
 * read for large meshes (roi count entries). With DFM_SCALAR_FLOAT64 and
 * stride 0 the bytes are exactly those the frame's checksum covers. */
DFM_API dfm_result dfm_session_read_roi_positions(dfm_session* session, const dfm_vec3_output* out,
                                                  dfm_frame_info* info);

/* The host's own vertex buffer, interleaved: vertex i starts at
 * (char*)data + i * stride; its position (float x y z) lies at
 * position_offset within it and its unit normal (float x y z) at
 * normal_offset. Other bytes are never touched. */
typedef struct dfm_vertex_output {
    uint32_t struct_size;   /* sizeof(dfm_vertex_output); see the conventions */
    void* data;             /* the host's buffer; vertex i at (char*)data + i * stride */
    size_t count;           /* capacity in vertices: at least the mesh's vertex_count */
    size_t stride;          /* at least 12 bytes past each field written */
    size_t position_offset; /* bytes from a vertex's start to its float x y z position */
    size_t normal_offset;   /* bytes from a vertex's start to its float x y z normal */
    bool write_positions;   /* write the positions */
    bool write_normals;     /* write the normals */
    /* Only what the session can change: the ROI's positions and the normals
     * the edit changes; the host keeps the rest from an earlier full read. */
    bool changed_only;
} dfm_vertex_output;

/* Writes the newest frame's positions and normals into the host's
 * interleaved buffer in one call, both from the same frame (rest values
 * for the vertices the session does not move, unless changed_only), and
 * its info into `info` (may be NULL). Thread safety as the other reads. */
DFM_API dfm_result dfm_session_read_vertices(dfm_session* session, const dfm_vertex_output* out,
                                             dfm_frame_info* info);

/* A frame lent to the host without copying: the newest frame's arrays, valid
 * until dfm_session_release_frame. All pointers belong to the session. */
typedef struct dfm_frame_view {
    const float* roi_positions;      /* x y z per ROI vertex, in roi_vertices order */
    const double* roi_positions_f64; /* the same in double (what the checksum covers) */
    const uint32_t* roi_vertices;    /* the ROI, ascending (as dfm_roi_read) */
    size_t roi_count;                /* entries of the three roi_ arrays */
    const float* normals;            /* x y z unit normal per entry of normal_vertices */
    const uint32_t* normal_vertices; /* every vertex whose normal the edit changes */
    size_t normal_count;             /* entries of normals and normal_vertices; 0 while preparing */
} dfm_frame_view;

/* Lends the newest frame: the cheapest read, constant time whatever the ROI
 * size. Solves keep publishing into other buffers meanwhile. One frame
 * may be held per session, and the hold is the session's, not a thread's:
 * a second acquire, from any thread, is DFM_ERROR_BUSY, and
 * dfm_session_release_frame from any thread gives the frame back. Other vertices
 * keep their rest positions and normals (dfm_mesh_read_positions).
 * On a mesh with split copies (dfm_mesh_desc) the view holds one entry per
 * surface vertex: roi_vertices and normal_vertices name each by its lowest
 * host index, and the host gives that entry's value to every copy
 * (dfm_mesh_read_surface_map); translating normal_vertices then costs one
 * pass over them on acquire. */
DFM_API dfm_result dfm_session_acquire_frame(dfm_session* session, dfm_frame_view* out,
                                             dfm_frame_info* info);

/* Gives the session's held frame back, whichever thread acquired it.
 * DFM_ERROR_INVALID_ARGUMENT when none is held. */
DFM_API dfm_result dfm_session_release_frame(dfm_session* session);

/* Bakes the newest finished frame, exactly as published (never a new
 * solve; staged targets are not looked at), into the mesh's rest pose
 * (undoable with dfm_mesh_undo_bake). Queued and running solves are
 * dropped (cancelled, as by dfm_session_cancel, before the new rest pose
 * is added: so also when adding it fails, because another thread changed
 * the rest pose meanwhile (DFM_ERROR_BUSY) or memory ran out). The
 * session then restarts on the new rest pose with the same
 * ROI and groups and identity transforms: its set-up is queued as
 * at creation (frames report `preparing`), and generations go on growing:
 * the restarted session's first frame carries the baked frame's
 * generation, and the next submit a generation above every earlier one.
 * DFM_ERROR_BUSY while the mesh's current rest pose is not the one the
 * session edits (after another bake, an undo, or dfm_mesh_set_positions;
 * undo and redo that bring the session's own pose back make it current
 * again, and the session may bake), while a frame is held
 * (dfm_session_acquire_frame), or while the session is preparing; a
 * session whose set-up failed reports that failure.
 * The frame is baked as solved, not as the targets ask: a solve lands
 * within a few tolerances of the exact shape, so a frame of identity
 * transforms after a drag differs from the rest pose by about that much,
 * and baking it moves the rest pose by that much (dfm_mesh_undo_bake
 * returns the exact pose; the untouched start frame bakes without a
 * change). Not concurrent with other calls on the session. */
DFM_API dfm_result dfm_session_bake(dfm_session* session);

/* The same for the finished frame of generation `generation`, which must
 * be the newest finished frame (the one the host last saw finish):
 * DFM_ERROR_NOT_FOUND when a newer finished frame has replaced it (the
 * message gives the newest); 0 means the newest finished frame. */
DFM_API dfm_result dfm_session_bake_generation(dfm_session* session, uint64_t generation);

/* ================================================================ reports
 * What a tool needs to report an edit as docs/scenarios.md describes it
 * ("The report"): the quality figures of a frame, the solver's figures, and
 * Loop subdivision for the scale cases. The Water-Filling diagnosis is
 * dfm_water_fill_diagnosis above. */

/* The quality figures of a frame, computed from the rest and deformed
 * positions alone. Lengths are fractions of the rest bounding-box diagonal. */
typedef struct dfm_quality {
    double max_handle_error;       /* largest distance of a handle vertex from its target */
    double mean_abs_log_edge;      /* over edges with a ROI endpoint, |log(new / rest length)| */
    double max_abs_log_edge;       /* the largest of those */
    double mean_normal_change_deg; /* mean turn of the face normals, faces with a ROI vertex */
    double max_fixed_move;         /* largest move of a vertex outside the ROI; always 0 */
    double dual_magnitude_error;   /* mean | |l_f| - |h_f| | over ROI faces / mean |h_f| */
    size_t flipped_faces;          /* faces with a ROI vertex whose normal turned over 90 deg */
    size_t creased_edges;          /* edges between ROI vertices whose dihedral angle turned
                                      over 90 deg: a fold's creases, blind to rigid motion */
} dfm_quality;

/* Measures the newest frame against the rest pose and the targets staged
 * now (so call it after the solve or wait that gave the frame, before
 * staging others). `info` (may be NULL) says which frame. Thread safety as
 * dfm_session_read_positions. */
DFM_API dfm_result dfm_session_measure_quality(dfm_session* session, dfm_quality* out,
                                               dfm_frame_info* info);

/* The solver's figures: the system's set-up (fixed for the session, new
 * after a bake) and the newest frame's linear solves. */
typedef struct dfm_solve_report {
    size_t unknowns;          /* vertices the solve moves */
    size_t rows;              /* dual Laplacian rows of the system */
    size_t normal_nonzeros;   /* stored entries of the normal matrix */
    double setup_ms;          /* the set-up: the frames' normals, assembly, factor */
    size_t krylov_iterations; /* inner iterations of the frame's solve, in total */
    double linear_residual; /* ||b - N x|| / ||b|| of its final verified solve; NaN if unverified */
    bool linear_converged;  /* that solve reached its tolerance */
} dfm_solve_report;

/* Fills *out for the newest frame; `info` (may be NULL) says which frame.
 * Thread safety as dfm_session_read_positions. */
DFM_API dfm_result dfm_session_get_solve_report(dfm_session* session, dfm_solve_report* out,
                                                dfm_frame_info* info);

/* Where the set-up and the newest frame's solve spent their time, and how
 * that frame started: what a benchmark reports beside dfm_solve_report. */
typedef struct dfm_solve_details {
    uint32_t struct_size; /* sizeof(dfm_solve_details); see the conventions */
    /* dfm_solve_report.setup_ms in parts, ms (the rest: the frames' normals,
     * the unknowns, the iteration's arrays) */
    double setup_rows_ms;     /* collecting the system's rows */
    double setup_assembly_ms; /* assembling the normal matrix */
    double setup_ordering_ms; /* the factor's fill-reducing ordering */
    double setup_symbolic_ms; /* the factor's symbolic phase */
    double setup_numeric_ms;  /* the factor's numeric phase */
    /* dfm_frame_info.solve_ms in parts, ms summed over the frame's iterations */
    double linear_solve_ms;    /* the linear solves */
    double right_hand_side_ms; /* the right-hand sides */
    double normals_ms;         /* the dual targets: normals (paper), or the rotation fit with
                                  its rows of the right-hand side (fitted rotations) */
    double anderson_ms;        /* the Anderson acceleration steps */
    bool predicted;            /* the frame started from the extrapolation of the two
                                  before it (dfm_solver_settings.disable_prediction) */
} dfm_solve_details;

/* Fills *out for the session's set-up and its newest frame; the caller sets
 * out->struct_size, and the library writes only that many bytes (0 stands
 * for the size the struct had when it appeared).
 * `info` (may be NULL) says which frame. Thread safety as
 * dfm_session_read_positions. */
DFM_API dfm_result dfm_session_get_solve_details(dfm_session* session, dfm_solve_details* out,
                                                 dfm_frame_info* info);

/* A new mesh: `steps` (1 to 3) rounds of Loop subdivision of the mesh's
 * current rest pose. The coarse vertices keep their indices, so vertex
 * indices chosen on the coarse mesh keep their meaning. A mesh with split
 * copies (dfm_mesh_desc) is refused (DFM_ERROR_UNSUPPORTED): its numbering
 * would not survive. *out is owned by the caller. Thread-safe. */
DFM_API dfm_result dfm_mesh_subdivide(const dfm_mesh* mesh, uint32_t steps, dfm_mesh** out);

/* What loading a file found besides the mesh (dfm_mesh_load_with_report). */
typedef struct dfm_load_report {
    size_t polygons;              /* faces as the file lists them */
    size_t triangulated_polygons; /* polygons of more than three corners, fanned */
    size_t dropped_faces;         /* triangles dropped for repeating a vertex */
} dfm_load_report;

/* dfm_mesh_load, and what the file held besides the mesh into *report (the
 * caller's; zeroed on failure). Errors, log and ownership as dfm_mesh_load.
 * Thread-safe. */
DFM_API dfm_result dfm_mesh_load_with_report(dfm_context* context, const char* path,
                                             dfm_load_report* report, dfm_mesh** out);

/* A mesh's topology and shape figures, beyond dfm_mesh_info. */
typedef struct dfm_mesh_summary {
    size_t edges;                /* distinct edges */
    size_t boundary_edges;       /* edges with one triangle */
    size_t non_manifold_edges;   /* edges with more than two triangles */
    size_t inconsistent_edges;   /* edges two triangles run the same way */
    size_t components;           /* connected components */
    size_t isolated_vertices;    /* vertices of no triangle */
    size_t degenerate_triangles; /* of zero area, relative to the diagonal */
    bool closed;                 /* no boundary and no non-manifold edge */
} dfm_mesh_summary;

/* Fills *out for the mesh's current rest pose. Thread-safe. */
DFM_API dfm_result dfm_mesh_get_summary(const dfm_mesh* mesh, dfm_mesh_summary* out);

/* How dfm_mesh_save_with_options writes PLY. */
typedef enum dfm_ply_encoding {
    DFM_PLY_BINARY_LITTLE_ENDIAN = 0, /* the default */
    DFM_PLY_BINARY_BIG_ENDIAN = 1,
    DFM_PLY_ASCII = 2
} dfm_ply_encoding;

/* Options of dfm_mesh_save_with_options; zero: dfm_mesh_save's output. */
typedef struct dfm_save_options {
    uint32_t struct_size;          /* sizeof(dfm_save_options); see the conventions */
    dfm_ply_encoding ply_encoding; /* PLY only */
    bool ply_float;                /* PLY coordinates as float (default double, exact) */
    bool obj_normals;              /* OBJ: area-weighted vertex normals, faces as v//vn */
    /* glTF, for a mesh loaded from glTF: keep the asset's positions and add
     * the edit (the rest pose minus the asset's positions, and the normals'
     * change) as a morph target of this name on every primitive of each
     * mesh it touches, existing targets kept, weights extended with 0 and
     * mesh.extras.targetNames with the name. FBX, for a mesh loaded from
     * FBX: the same as a blend shape channel of this name (weight 0) on
     * each geometry the edit moves. NULL or "": write the new positions
     * instead. Copied during the call. */
    const char* morph_target_name;
} dfm_save_options;

/* dfm_mesh_save with options (NULL: the defaults). DFM_ERROR_INVALID_ARGUMENT
 * for an unknown encoding. Thread-safe. */
DFM_API dfm_result dfm_mesh_save_with_options(const dfm_mesh* mesh, const char* path,
                                              const dfm_save_options* options);

#ifdef __cplusplus
}
#endif

#endif
