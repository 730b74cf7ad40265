/* What the samples read from the environment and hand to Dualform through
 * its descriptors: the library itself reads no environment variable. */
#ifndef DUALFORM_SAMPLE_ENVIRONMENT_H
#define DUALFORM_SAMPLE_ENVIRONMENT_H

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The folder for model:NAME (dfm_context_desc.models_directory):
 * $DUALFORM_MODELS, or $HOME/.cache/dualform/models where tools/fetch-models
 * puts the real models. Written into `buffer`; NULL when neither variable is
 * set or the path does not fit. */
static inline const char* sample_models_folder(char* buffer, size_t size) {
    const char* dir = getenv("DUALFORM_MODELS");
    const char* home = getenv("HOME");
    int written = -1;
    if (dir != NULL && dir[0] != '\0') {
        written = snprintf(buffer, size, "%s", dir);
    } else if (home != NULL && home[0] != '\0') {
        written = snprintf(buffer, size, "%s/.cache/dualform/models", home);
    }
    return written >= 0 && (size_t)written < size ? buffer : NULL;
}

/* DUALFORM_VALIDATION=1: turn on the Vulkan validation layer
 * (dfm_vk_renderer_desc.validation). */
static inline bool sample_validation(void) {
    const char* value = getenv("DUALFORM_VALIDATION");
    return value != NULL && strcmp(value, "1") == 0;
}

#endif
