/* libsweep: the sweep runtime behind a C interface, for any engine or FFI (C, C#, Rust, Python's
 * ctypes...). One instance is one character: a rig, its binding, the mesh's rest positions and
 * optional scene settings, read once; then each frame the game gives the body's pose and any
 * forces, advances by its frame time, and reads the deformed positions back.
 *
 * Time: the instance keeps its own clock of internal steps (the settings' "step"; settings that
 * give none, or none at all, take 1/60 s with the exact integrator: one step a 60 fps frame, where
 * sweep-sim takes 1/480 s) and reaches any time by one exact partial step beyond the last one, so
 * the motion does not depend on how the game slices time: advancing by 1/60, 1/144, 1/30 ... lands
 * on the same pose at the same times as regular frames.
 *
 * Errors: every int function returns 0, or an error code in the categories of the tools' exit
 * codes (SWEEP_ERROR_*); sweep_open returns NULL. sweep_last_error() then tells what went wrong,
 * for the calling thread. A bad argument (NULL, NaN, an unknown part, a negative dt, a matrix that
 * is not rigid) is refused with an error and changes nothing; it never crashes the host. After a
 * simulation diverged (SWEEP_ERROR_DIVERGED) the instance refuses to advance: close it.
 *
 * Threads: an instance is used by one thread at a time; different instances run on any threads.
 * An instance's calls run on the calling thread alone (a creature's frame is too little work to
 * share): spread the creatures over the game's threads. */
#ifndef SWEEP_SWEEP_H
#define SWEEP_SWEEP_H

#if defined(_WIN32) && defined(SWEEP_BUILDING_LIBRARY)
#define SWEEP_API __declspec(dllexport)
#elif defined(_WIN32)
#define SWEEP_API __declspec(dllimport)
#elif defined(__GNUC__)
#define SWEEP_API __attribute__((visibility("default")))
#else
#define SWEEP_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* The error codes: the exit codes of sweep-fit, sweep-bind and sweep-sim (docs/tools.md, "Exit codes"). */
enum {
  SWEEP_OK = 0,
  SWEEP_ERROR_USAGE = 1,       /* a bad argument: NULL, NaN, unknown part, dt < 0, non-rigid pose */
  SWEEP_ERROR_BAD_INPUT = 2,   /* a file is missing, unreadable, malformed or does not match */
  SWEEP_ERROR_UNSUPPORTED = 3, /* valid input this version cannot handle */
  SWEEP_ERROR_OUTPUT = 4,
  SWEEP_ERROR_DIVERGED = 5, /* the simulation diverged (explicit integrators) */
  SWEEP_ERROR_INTERNAL = 6  /* a bug, or out of memory */
};

typedef struct sweep_instance sweep_instance;

/* Reads the rig (.rig.json), its binding (.bind, from sweep-bind) and optional settings: a scene
 * file (NULL: the defaults) whose settings apply (gravity, step, integrator, colliders, wind) and
 * whose forces and body keys, if any, also play. rest_xyz: the mesh's vertex_count rest positions,
 * x y z each, in the order the binding was made for (they are checked against it). NULL on error. */
SWEEP_API sweep_instance* sweep_open(const char* rig_path, const char* binding_path, const char* settings_path,
                                     const float* rest_xyz, int vertex_count);
/* Frees everything the instance holds; NULL is allowed and does nothing. */
SWEEP_API void sweep_close(sweep_instance* instance);
/* The last failed call's message on this thread ("" if none); valid until this thread's next call. */
SWEEP_API const char* sweep_last_error(void);

/* The body's pose (world from mesh: a rigid 4×4 matrix, column-major, last row 0 0 0 1) at the end
 * of the next sweep_advance. Across that advance the body moves from its pose now to it: translation
 * straight, rotation by slerp, at constant speed; the parts feel that motion (its change of
 * velocity from the last advance is a kick). Given before the first advance, it is also where the
 * body starts, at rest. Not given, the body holds its last pose. */
SWEEP_API int sweep_set_body(sweep_instance* instance, const double world_from_mesh[16]);
/* A force (N, world axes) at the surface point of `part` nearest `point` (world), from now on for
 * `seconds`; seconds 0: an impulse of `force` N·s now. It acts exactly as a scene force with that
 * point, vector and times and the scene's defaults (components, nearest sections, physical moment
 * in material mode). */
SWEEP_API int sweep_add_force(sweep_instance* instance, const char* part, const double point[3], const double force[3],
                              double seconds);
/* Advances the instance's clock by dt ≥ 0 seconds. What the game reads is computed when it reads it:
 * sweep_positions deforms, and sweep_joints poses, only the parts that moved since they last did. */
SWEEP_API int sweep_advance(sweep_instance* instance, double dt);
/* The deformed positions at the current time, world space: vertex_count × 3 floats. */
SWEEP_API int sweep_positions(const sweep_instance* instance, float* out_xyz);
/* The same in the mesh's own space, for an engine that draws the mesh under the body's transform
 * itself (world = world_from_mesh · these): vertex_count × 3 floats. No part moves the vertices it
 * does not bind: they are their rest positions (rest_xyz of sweep_open), in every frame. */
SWEEP_API int sweep_positions_local(const sweep_instance* instance, float* out_xyz);
/* Only the vertices the parts bind, for an engine that keeps the mesh's buffer between frames and
 * updates the part of it that moves. sweep_bound_count: how many (0 to vertex_count), or minus an
 * error code. sweep_bound_indices: their mesh indices (0-based), sweep_bound_count ints, fixed for
 * the instance's life: read them once. sweep_bound_positions: their deformed positions at the
 * current time, mesh space as sweep_positions_local, x y z each, in sweep_bound_indices' order
 * (out_xyz[3i..3i+2] is vertex indices[i]). */
SWEEP_API int sweep_bound_count(const sweep_instance* instance);
SWEEP_API int sweep_bound_indices(const sweep_instance* instance, int* out_indices);
SWEEP_API int sweep_bound_positions(const sweep_instance* instance, float* out_xyz);
/* The joints of the skinned export (`sweep-sim --joints`), for an engine that skins on the GPU: it
 * loads the exported .glb (mesh, weights, inverse bind matrices) once and each frame reads these
 * instead of the positions. sweep_joint_count: how many (the body joint included), or minus an error
 * code. sweep_joints: each joint's world matrix (world from joint, column-major, 16 floats a joint),
 * in the order `sweep-sim --joints` writes them (the .glb's skin joints: the body, then per part its
 * station joints and their ring joints). The skeleton is that of `--joints` given alone (24 joints
 * along each part, 24 around each station but the root) until sweep_set_skin says otherwise; an
 * export made with --ring-fit has its ring joints fitted to the bake, which a live frame samples. */
SWEEP_API int sweep_joint_count(const sweep_instance* instance);
SWEEP_API int sweep_joints(const sweep_instance* instance, float* out_16xN);
/* on = 1 (the default, as sweep-sim): each internal step evaluates the loads that follow the moving
 * parts (forces, the body's motion and gravity in the parts' axes) at the predicted mid-step pose.
 * on = 0: it takes the start-of-step loads over the whole step, for half the step's work; the error
 * then grows with how far a part turns within a step (README, "Time", gives it measured). */
SWEEP_API int sweep_set_predictor(sweep_instance* instance, int on);
/* Material-mode parts move as the modes of their chain of sections. on = 0 (the default): the
 * modes the internal step resolves move (at most a period a step: up to 60 Hz at the live 1/60 s),
 * the faster ones follow the loads quasi-statically. A settled part's shape is the same; what goes
 * is the fast modes' own ringing, which the steps cannot sample, and a step reads a fraction of each
 * part's modes. on = 1: every mode moves, as sweep-sim's bakes (a step's work and data then grow as
 * the square of the sections). */
SWEEP_API int sweep_set_all_modes(sweep_instance* instance, int on);
/* The skeleton the export was made with: `sweep-sim --joints joints_per_sweep --ring-joints
 * ring_joints` (2 to 255 joints a part, at most its stations; 1 to 64 ring joints, 1 = none). */
SWEEP_API int sweep_set_skin(sweep_instance* instance, int joints_per_sweep, int ring_joints);

#ifdef __cplusplus
}
#endif

#endif /* SWEEP_SWEEP_H */
