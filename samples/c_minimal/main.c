/*
 * c_minimal: the smallest Dualform host, in plain C99.
 *
 * Loads the cow, selects its front leg with two clicks through a camera
 * (Water-Filling), drags the hoof over 60 frames without ever waiting on the
 * solver, then bakes the newest result and writes the mesh.
 *
 * usage: c_minimal [MESH] [OUT]     defaults: model:cow c_minimal_cow.off
 */
#define _POSIX_C_SOURCE 199309L /* nanosleep stands in for the host's frame pacing */

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <dualform/dualform.h>

#include "../common/sample_environment.h"

static int ok(dfm_result result, const char* call) {
    if (result == DFM_OK) return 1;
    fprintf(stderr, "c_minimal: %s: %s: %s\n", call, dfm_result_name(result),
            dfm_last_error_message());
    return 0;
}

int main(int argc, char** argv) {
    const char* mesh_path = argc > 1 ? argv[1] : "model:cow";
    const char* out_path = argc > 2 ? argv[2] : "c_minimal_cow.off";
    /* The cow seen from its left: the first click is on the front hoof, the
     * second just above the knee, where the region should end. */
    const dfm_camera camera = {{0.0, 0.0, -2.5}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 30.0, 640, 480};
    const double hoof_click[2] = {273.7, 351.9};
    const double knee_click[2] = {274.5, 279.8};

    dfm_context* context = NULL;
    dfm_mesh* mesh = NULL;
    dfm_roi* leg = NULL;
    dfm_roi* hoof = NULL;
    dfm_session* session = NULL;
    uint32_t* hoof_vertices = NULL;
    int status = 1;

    char models[4096];
    dfm_context_desc context_desc = {0};
    dfm_mesh_info info = {0};
    dfm_water_fill_diagnosis diagnosis = {0};
    dfm_hit hit = {0};
    size_t leg_size = 0, hoof_size = 0;
    context_desc.models_directory = sample_models_folder(models, sizeof models);
    if (!ok(dfm_context_create(&context_desc, &context), "dfm_context_create")) goto done;
    if (!ok(dfm_mesh_load(context, mesh_path, &mesh), "dfm_mesh_load")) goto done;
    if (!ok(dfm_mesh_get_info(mesh, &info), "dfm_mesh_get_info")) goto done;

    if (!ok(dfm_roi_water_fill_clicks(mesh, &camera, hoof_click, knee_click, &leg, &diagnosis),
            "dfm_roi_water_fill_clicks")) {
        goto done;
    }
    if (diagnosis.suspect) {
        fprintf(stderr, "c_minimal: the region looks wrong (%zu cut loops); not editing\n",
                diagnosis.loops);
        goto done;
    }
    /* The handle: the vertices within 3% of the diagonal of the clicked hoof. */
    if (!ok(dfm_mesh_pick(mesh, &camera, hoof_click[0], hoof_click[1], &hit), "dfm_mesh_pick")) {
        goto done;
    }
    if (!ok(dfm_roi_ball(mesh, hit.vertex, 0.03, &hoof), "dfm_roi_ball")) goto done;
    dfm_roi_count(leg, &leg_size);
    dfm_roi_count(hoof, &hoof_size);
    hoof_vertices = malloc(hoof_size * sizeof *hoof_vertices);
    if (hoof_vertices == NULL) goto done;
    if (!ok(dfm_roi_read(hoof, hoof_vertices, hoof_size), "dfm_roi_read")) goto done;

    {
        dfm_handle_group group = {0};
        dfm_session_desc desc = {0};
        group.vertices = hoof_vertices;
        group.count = hoof_size;
        desc.roi = leg;
        desc.groups = &group;
        desc.group_count = 1;
        if (!ok(dfm_session_create(mesh, &desc, &session), "dfm_session_create")) goto done;
    }

    {
        /* The host's frame loop: set the handle's transform, submit, and pick
         * up whatever result is newest. Nothing here waits on the solver. */
        uint64_t shown = 0, submitted = 0;
        int frame, results = 0;
        dfm_frame_info last = {0};
        for (frame = 1; frame <= 60; ++frame) {
            const double t = frame / 60.0;
            double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
            dfm_frame_info now = {0};
            bool is_new = false;
            m[12] = 0.08 * t * info.diagonal; /* forward */
            m[13] = 0.03 * t * info.diagonal; /* and up */
            if (!ok(dfm_session_set_group_transform(session, 0, m), "set_group_transform")) {
                goto done;
            }
            if (!ok(dfm_session_submit(session, &submitted), "dfm_session_submit")) goto done;
            if (!ok(dfm_session_poll(session, shown, &now, &is_new), "dfm_session_poll")) goto done;
            if (is_new) {
                shown = now.generation;
                ++results;
            }
            {
                /* The rest of the host's 60 Hz frame: rendering, gameplay. */
                const struct timespec frame_time = {0, 16000000L};
                nanosleep(&frame_time, NULL);
            }
        }
        /* The end of the drag: this one time, wait for the final result. */
        if (!ok(dfm_session_wait(session, submitted, -1, &last), "dfm_session_wait")) goto done;
        printf(
            "{\"roi\": %zu, \"handle\": %zu, \"frames\": 60, \"results_during_drag\": %d, "
            "\"final_generation\": %llu, \"iterations\": %u, \"converged\": %s}\n",
            leg_size, hoof_size, results, (unsigned long long)last.generation, last.iterations,
            last.converged ? "true" : "false");
    }

    if (!ok(dfm_session_bake(session), "dfm_session_bake")) goto done;
    if (!ok(dfm_mesh_save(mesh, out_path), "dfm_mesh_save")) goto done;
    status = 0;

done:
    free(hoof_vertices);
    dfm_session_destroy(session);
    dfm_roi_destroy(hoof);
    dfm_roi_destroy(leg);
    dfm_mesh_destroy(mesh);
    dfm_context_destroy(context);
    return status;
}
