/* movie.c: a movie from numbered PNG frames, made by running ffmpeg (when it is on PATH) into a
 * temporary file that is renamed over the output when ffmpeg succeeds. */
#include "mote/render.h"

#include <errno.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

/* The first executable `name` in PATH, or NULL (malloc'ed). */
static char *find_in_path(const char *name)
{
    const char *path = getenv("PATH");
    if (!path)
        return NULL;
    size_t nl = strlen(name);
    while (*path) {
        size_t n = strcspn(path, ":");
        char *full = malloc(n + nl + 2);
        if (!full)
            return NULL;
        if (n == 0) {
            memcpy(full, name, nl + 1);
        } else {
            memcpy(full, path, n);
            full[n] = '/';
            memcpy(full + n + 1, name, nl + 1);
        }
        struct stat st;
        if (stat(full, &st) == 0 && S_ISREG(st.st_mode) && access(full, X_OK) == 0)
            return full;
        free(full);
        path += n;
        if (*path == ':')
            path++;
    }
    return NULL;
}

extern char **environ;

int mote_movie(const char *prefix, int64_t fps, const char *out, FILE *diag, int *ran,
               mote_err *err)
{
    *ran = 0;
    size_t pl = strlen(prefix);
    char *pattern = malloc(pl + 16);
    if (!pattern)
        return mote_fail(err, MOTE_ENOMEM, "movie: out of memory");
    snprintf(pattern, pl + 16, "%s%s%%06d.png", prefix, mote_series_sep(prefix));
    const char *slash = strrchr(out, '/');
    const char *dot = strrchr(out, '.');
    const char *ext = dot && (!slash || dot > slash) ? dot : "";
    int gif = strcmp(ext, ".gif") == 0;
    char rate[32];
    snprintf(rate, sizeof rate, "%lld", (long long)fps);
    char *ffmpeg = find_in_path("ffmpeg");
    if (!ffmpeg) {
        if (diag)
            fprintf(diag,
                    "note: movie: ffmpeg is not on PATH, so no movie was made; with ffmpeg "
                    "installed, run:\n  ffmpeg -y -framerate %s -i '%s' -vf "
                    "'pad=ceil(iw/2)*2:ceil(ih/2)*2'%s '%s'\n",
                    rate, pattern, gif ? "" : " -pix_fmt yuv420p", out);
        free(pattern);
        return MOTE_OK;
    }
    size_t ol = strlen(out);
    char *tmp = malloc(ol + 48);
    if (!tmp) {
        free(pattern);
        free(ffmpeg);
        return mote_fail(err, MOTE_ENOMEM, "movie: out of memory");
    }
    /* ffmpeg picks the container from the extension, so the temporary name keeps it. */
    snprintf(tmp, ol + 48, "%.*s.tmp%ld%s", (int)(ol - strlen(ext)), out, (long)getpid(), ext);
    char *argv[20];
    int k = 0;
    argv[k++] = "ffmpeg";
    argv[k++] = "-y";
    argv[k++] = "-loglevel";
    argv[k++] = "error";
    argv[k++] = "-framerate";
    argv[k++] = rate;
    argv[k++] = "-i";
    argv[k++] = pattern;
    argv[k++] = "-vf";
    argv[k++] = "pad=ceil(iw/2)*2:ceil(ih/2)*2";
    if (!gif) {
        argv[k++] = "-pix_fmt";
        argv[k++] = "yuv420p";
    }
    argv[k++] = tmp;
    argv[k] = NULL;
    if (diag)
        fflush(diag);
    pid_t pid;
    int rc = MOTE_OK;
    int e = posix_spawn(&pid, ffmpeg, NULL, NULL, argv, environ);
    if (e != 0) {
        rc = mote_fail(err, MOTE_EIO, "movie: cannot start %s: %s", ffmpeg, strerror(e));
    } else {
        int status = 0;
        while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
            ;
        if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
            rc = mote_fail(err, MOTE_ERUNTIME, "movie: ffmpeg failed (%s %d) making '%s' from '%s'",
                           WIFEXITED(status) ? "exit status" : "signal",
                           WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status), out,
                           pattern);
        else if (rename(tmp, out) != 0)
            rc = mote_fail(err, MOTE_EIO, "movie: cannot write '%s': %s", out, strerror(errno));
        else
            *ran = 1;
    }
    if (rc)
        unlink(tmp);
    free(tmp);
    free(pattern);
    free(ffmpeg);
    return rc;
}

