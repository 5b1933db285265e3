/* _mote.c: the Python package's C extension over libmote (CPython API and NumPy's C API, from
 * Debian's python3-dev and python3-numpy). What the package's __init__.py builds on:
 *   run(text, name, params, check_only, progress) -> (printed, warnings)
 *   Session(model_line, name): command(text) -> printed, status() -> str, arrays() -> list of
 *     (name, ndarray, unit, is_view), set_array(name, ndarray), close()
 *   MoteError: the message mote prints ("FILE:LINE:COL: error: ...")
 * Runs release the GIL, so Python threads go on meanwhile; the progress callback takes it
 * again to be called. Views of a model's arrays are read-only, and a session refuses to run a
 * command while one is alive (its memory could move), so no view ever outlives its data. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mote/command.h"
#include "mote/script.h"

static PyObject *MoteError;

/* ---- output into memory ---------------------------------------------------------------------- */

/* The text written to f since its start (f emptied). */
static PyObject *take(FILE *f)
{
    fflush(f);
    long n = ftell(f);
    char *buf = malloc(n > 0 ? (size_t)n + 1 : 1);
    if (!buf)
        return PyErr_NoMemory();
    rewind(f);
    size_t got = n > 0 ? fread(buf, 1, (size_t)n, f) : 0;
    rewind(f);
    PyObject *s = PyUnicode_DecodeUTF8(buf, (Py_ssize_t)got, "replace");
    free(buf);
    return s;
}

static PyObject *fail(const mote_err *err, PyObject *printed)
{
    PyObject *exc = PyObject_CallFunction(MoteError, "s", err->msg);
    if (exc) {
        PyObject_SetAttrString(exc, "printed", printed ? printed : Py_None);
        PyErr_SetObject(MoteError, exc);
        Py_DECREF(exc);
    }
    Py_XDECREF(printed);
    return NULL;
}

/* ---- progress --------------------------------------------------------------------------------- */

static void report(void *arg, const char *label, double fraction)
{
    PyGILState_STATE g = PyGILState_Ensure();
    PyObject *r = PyObject_CallFunction((PyObject *)arg, "sd", label, fraction);
    if (!r && PyErr_ExceptionMatches(PyExc_KeyboardInterrupt)) {
        PyErr_Clear(); /* Ctrl-C during the callback: the command stops as for one outside it */
        PyErr_SetInterrupt();
    } else if (!r) { /* (another exception in the callback is shown, and the run goes on) */
        PyErr_WriteUnraisable((PyObject *)arg);
    }
    Py_XDECREF(r);
    PyGILState_Release(g);
}

/* ---- Ctrl-C -------------------------------------------------------------------------------- */

/* The exception a signal raised while a command ran (KeyboardInterrupt), kept for after it. */
typedef struct {
    PyObject *type, *value, *tb;
} pending_exc;

/* The context's interrupt hook: runs Python's signal handlers (in the main thread); when one
 * raised, the command is asked to stop at its next safe point, and the exception is raised when
 * it has returned. */
static int interrupt_hook(void *arg)
{
    pending_exc *pe = arg;
    if (pe->type)
        return 1;
    PyGILState_STATE g = PyGILState_Ensure();
    int stop = 0;
    if (PyErr_CheckSignals() != 0) {
        PyErr_Fetch(&pe->type, &pe->value, &pe->tb);
        stop = pe->type != NULL;
    }
    PyGILState_Release(g);
    return stop;
}

/* After a command: the pending exception raised (1), or 0. */
static int raise_pending(pending_exc *pe)
{
    if (!pe->type)
        return 0;
    PyErr_Restore(pe->type, pe->value, pe->tb);
    pe->type = pe->value = pe->tb = NULL;
    return 1;
}

/* ---- run ------------------------------------------------------------------------------------- */

static PyObject *py_run(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"text", "name", "params", "check_only", "progress", NULL};
    const char *text, *name;
    Py_ssize_t len;
    PyObject *params = NULL, *progress = Py_None;
    int check_only = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "s#s|OpO", kwlist, &text, &len, &name, &params,
                                     &check_only, &progress))
        return NULL;
    Py_ssize_t np = params && params != Py_None ? PySequence_Size(params) : 0;
    if (np < 0)
        return NULL;
    const char **pv = calloc((size_t)np + 1, sizeof *pv);
    PyObject **keep = calloc((size_t)np + 1, sizeof *keep);
    if (!pv || !keep) {
        free(pv);
        free(keep);
        return PyErr_NoMemory();
    }
    for (Py_ssize_t i = 0; i < np; i++) {
        keep[i] = PySequence_GetItem(params, i);
        pv[i] = keep[i] ? PyUnicode_AsUTF8(keep[i]) : NULL;
        if (!pv[i]) {
            for (Py_ssize_t k = 0; k <= i; k++)
                Py_XDECREF(keep[k]);
            free(pv);
            free(keep);
            return NULL;
        }
    }
    mote_err err = {0};
    pending_exc pe = {NULL, NULL, NULL};
    mote_script *s = NULL;
    FILE *out = tmpfile(), *diag = tmpfile();
    int rc = out && diag ? mote_script_parse_params(&s, name, text, (size_t)len, pv, (int)np,
                                                    mote_models, mote_nmodels, &err)
                         : MOTE_ENOMEM;
    for (Py_ssize_t k = 0; k < np; k++)
        Py_XDECREF(keep[k]);
    free(pv);
    free(keep);
    if (!out || !diag) {
        if (out)
            fclose(out);
        if (diag)
            fclose(diag);
        return PyErr_NoMemory();
    }
    if (!rc) {
        mote_context *ctx = mote_script_context(s);
        ctx->out = out;
        ctx->diag = diag;
        if (progress != Py_None) {
            ctx->report = report;
            ctx->report_arg = progress;
        }
        ctx->interrupt = interrupt_hook;
        ctx->interrupt_arg = &pe;
        Py_BEGIN_ALLOW_THREADS
        rc = mote_script_validate(s, &err);
        if (!rc && !check_only)
            rc = mote_script_execute(s, &err);
        Py_END_ALLOW_THREADS
        mote_script_free(s);
    }
    if (raise_pending(&pe)) {
        fclose(out);
        fclose(diag);
        return NULL;
    }
    PyObject *printed = take(out), *warnings = take(diag);
    fclose(out);
    fclose(diag);
    if (rc) {
        Py_XDECREF(warnings);
        return fail(&err, printed);
    }
    return Py_BuildValue("(NN)", printed, warnings);
}

/* ---- sessions -------------------------------------------------------------------------------- */

typedef struct {
    PyObject_HEAD
    mote_script *s;
    const mote_model *model;
    PyObject *views; /* list of weak references to the views handed out */
    PyObject *progress;
    int busy;        /* a command is running (in another thread) */
} Session;

static void Session_dealloc(Session *self)
{
    mote_session_close(self->s);
    Py_XDECREF(self->views);
    Py_XDECREF(self->progress);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static int Session_init(Session *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"model", "name", NULL};
    const char *model, *name = "<session>";
    if (!PyArg_ParseTupleAndKeywords(args, kw, "s|s", kwlist, &model, &name))
        return -1;
    mote_err err = {0};
    if (self->busy) {
        PyErr_SetString(MoteError, "the session is running a command in another thread");
        return -1;
    }
    mote_session_close(self->s);
    self->s = NULL;
    if (mote_session_open(&self->s, name, model, mote_models, mote_nmodels, &err)) {
        fail(&err, NULL);
        return -1;
    }
    self->model = mote_script_model(self->s);
    Py_XDECREF(self->views);
    self->views = PyList_New(0);
    return self->views ? 0 : -1;
}

static int need_open(Session *self)
{
    if (!self->s) {
        PyErr_SetString(MoteError, "the session is closed");
        return -1;
    }
    if (self->busy) {
        PyErr_SetString(MoteError, "the session is running a command in another thread");
        return -1;
    }
    return 0;
}

/* No view handed out may be alive while the model changes: its memory could move. */
static int no_live_views(Session *self)
{
    Py_ssize_t n = PyList_Size(self->views), alive = 0;
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *o = PyWeakref_GetObject(PyList_GetItem(self->views, i));
        alive += o != Py_None;
    }
    if (alive) {
        PyErr_Format(MoteError, "%zd view%s of the %s model's arrays %s still held; delete %s "
                     "(or take copies: Simulation.arrays()) before the next command", alive,
                     alive == 1 ? "" : "s", self->model->name, alive == 1 ? "is" : "are",
                     alive == 1 ? "it" : "them");
        return -1;
    }
    return PyList_SetSlice(self->views, 0, n, NULL);
}

static PyObject *Session_command(Session *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"text", "progress", NULL};
    const char *text;
    PyObject *progress = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "s|O", kwlist, &text, &progress))
        return NULL;
    if (need_open(self) || no_live_views(self))
        return NULL;
    mote_context *ctx = mote_script_context(self->s);
    ctx->report = progress != Py_None ? report : NULL;
    ctx->report_arg = progress;
    mote_err err = {0};
    char *printed = NULL;
    int rc;
    pending_exc pe = {NULL, NULL, NULL};
    ctx->interrupt = interrupt_hook;
    ctx->interrupt_arg = &pe;
    self->busy = 1;
    Py_BEGIN_ALLOW_THREADS
    rc = mote_session_command(self->s, text, &printed, &err);
    Py_END_ALLOW_THREADS
    self->busy = 0;
    ctx->report = NULL;
    ctx->interrupt = NULL;
    if (raise_pending(&pe)) { /* (Ctrl-C: the command stopped at a safe point) */
        free(printed);
        return NULL;
    }
    PyObject *p = PyUnicode_DecodeUTF8(printed ? printed : "", printed ? strlen(printed) : 0,
                                       "replace");
    free(printed);
    if (rc)
        return fail(&err, p);
    return p;
}

static PyObject *Session_status(Session *self, PyObject *unused)
{
    if (need_open(self))
        return NULL;
    char *st = mote_session_status(self->s);
    PyObject *r = PyUnicode_FromString(st ? st : "");
    free(st);
    return r;
}

/* The model's box: ((ex, ey, ez), (ox, oy, oz), (px, py, pz)) or None */
static PyObject *Session_cell(Session *self, PyObject *unused)
{
    if (need_open(self))
        return NULL;
    double e[3], o[3];
    int p[3];
    if (!self->model->cell || self->model->cell(mote_session_instance(self->s), e, o, p))
        Py_RETURN_NONE;
    return Py_BuildValue("((ddd)(ddd)(OOO))", e[0], e[1], e[2], o[0], o[1], o[2],
                         p[0] ? Py_True : Py_False, p[1] ? Py_True : Py_False,
                         p[2] ? Py_True : Py_False);
}

static void free_capsule(PyObject *cap) { free(PyCapsule_GetPointer(cap, NULL)); }

/* The model's arrays: [(name, ndarray, unit, is_view)]; views are read-only (copy=False) */
static PyObject *Session_arrays(Session *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"copy", NULL};
    int copy = 1;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|p", kwlist, &copy))
        return NULL;
    if (need_open(self))
        return NULL;
    PyObject *list = PyList_New(0);
    if (!list || !self->model->arrays)
        return list;
    mote_array a[16];
    int n = self->model->arrays(mote_session_instance(self->s), a, 16);
    if (n < 0) {
        Py_DECREF(list);
        return PyErr_NoMemory();
    }
    int bad = 0;
    for (int k = 0; k < n; k++) {
        if (bad) {
            if (a[k].owned)
                free(a[k].data);
            continue;
        }
        npy_intp dims[2] = {(npy_intp)a[k].rows, (npy_intp)a[k].cols};
        npy_intp strides[2] = {a[k].row_stride, a[k].col_stride};
        const int nd = a[k].cols == 1 ? 1 : 2;
        const int type = a[k].type == 'i' ? NPY_INT32 : NPY_DOUBLE;
        PyObject *arr = PyArray_New(&PyArray_Type, nd, dims, type, strides, a[k].data, 0,
                                    a[k].owned ? NPY_ARRAY_WRITEABLE : 0, NULL);
        int view = !a[k].owned;
        if (arr && a[k].owned) { /* the array owns the copy made for it */
            PyObject *cap = PyCapsule_New(a[k].data, NULL, free_capsule);
            if (!cap || PyArray_SetBaseObject((PyArrayObject *)arr, cap)) {
                Py_XDECREF(cap);
                Py_CLEAR(arr);
            }
        } else if (arr) {
            PyArray_CLEARFLAGS((PyArrayObject *)arr, NPY_ARRAY_WRITEABLE);
            Py_INCREF(self);
            if (PyArray_SetBaseObject((PyArrayObject *)arr, (PyObject *)self))
                Py_CLEAR(arr);
            if (arr && copy) { /* a copy, which the session need not watch */
                PyObject *c = PyArray_NewCopy((PyArrayObject *)arr, NPY_CORDER);
                Py_DECREF(arr);
                arr = c;
                view = 0;
            } else if (arr) {
                PyObject *ref = PyWeakref_NewRef(arr, NULL);
                if (!ref || PyList_Append(self->views, ref))
                    Py_CLEAR(arr);
                Py_XDECREF(ref);
            }
        }
        PyObject *t = arr ? Py_BuildValue("(sNsO)", a[k].name, arr, a[k].unit ? a[k].unit : "",
                                          view ? Py_True : Py_False)
                          : NULL;
        if (!t || PyList_Append(list, t)) {
            Py_XDECREF(t);
            bad = 1;
            continue;
        }
        Py_DECREF(t);
    }
    if (bad) {
        Py_DECREF(list);
        return NULL;
    }
    return list;
}

static PyObject *Session_set_array(Session *self, PyObject *args)
{
    const char *name;
    PyObject *obj;
    if (!PyArg_ParseTuple(args, "sO", &name, &obj))
        return NULL;
    if (need_open(self) || no_live_views(self))
        return NULL;
    if (!self->model->set_array) {
        PyErr_Format(MoteError, "set %s: the %s model's arrays cannot be set from Python", name,
                     self->model->name);
        return NULL;
    }
    PyArrayObject *a = (PyArrayObject *)PyArray_FROMANY(obj, NPY_DOUBLE, 1, 2, NPY_ARRAY_CARRAY);
    if (!a) {
        PyErr_Clear();
        PyErr_Format(MoteError, "set %s: expected a 1- or 2-dimensional array of numbers", name);
        return NULL;
    }
    const size_t rows = (size_t)PyArray_DIM(a, 0);
    const size_t cols = PyArray_NDIM(a) == 2 ? (size_t)PyArray_DIM(a, 1) : 1;
    mote_err err = {0};
    int rc = self->model->set_array(mote_session_instance(self->s), name, PyArray_DATA(a), rows,
                                    cols, &err);
    Py_DECREF(a);
    if (rc)
        return fail(&err, NULL);
    Py_RETURN_NONE;
}

static PyObject *Session_close(Session *self, PyObject *unused)
{
    if (self->busy) { /* (freeing the model under the running command crashed) */
        PyErr_SetString(MoteError, "close: the session is running a command in another thread; "
                                   "close it after the command returns");
        return NULL;
    }
    if (self->s && (no_live_views(self)))
        return NULL;
    mote_session_close(self->s);
    self->s = NULL;
    Py_RETURN_NONE;
}

static PyObject *Session_model(Session *self, void *unused)
{
    return PyUnicode_FromString(self->model ? self->model->name : "");
}

static PyMethodDef Session_methods[] = {
    {"command", (PyCFunction)(void (*)(void))Session_command, METH_VARARGS | METH_KEYWORDS,
     "command(text, progress=None) -> str: read, check and run the lines, return what they "
     "printed"},
    {"status", (PyCFunction)Session_status, METH_NOARGS, "the model's status line"},
    {"cell", (PyCFunction)Session_cell, METH_NOARGS,
     "the model's box: (edges, lower corner, periodic axes), or None"},
    {"arrays", (PyCFunction)(void (*)(void))Session_arrays, METH_VARARGS | METH_KEYWORDS,
     "arrays(copy=True) -> [(name, ndarray, unit, is_view)]"},
    {"set_array", (PyCFunction)Session_set_array, METH_VARARGS,
     "set_array(name, array): replace a state array after the model checks it"},
    {"close", (PyCFunction)Session_close, METH_NOARGS, "free the model"},
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef Session_getset[] = {
    {"model", (getter)Session_model, NULL, "the model's name", NULL},
    {NULL, NULL, NULL, NULL, NULL},
};

static PyTypeObject SessionType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "mote._mote.Session",
    .tp_basicsize = sizeof(Session),
    .tp_dealloc = (destructor)Session_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "Session(model, name='<session>'): a model driven command by command",
    .tp_methods = Session_methods,
    .tp_getset = Session_getset,
    .tp_init = (initproc)Session_init,
    .tp_new = PyType_GenericNew,
};

/* ---- the module ------------------------------------------------------------------------------ */

static PyObject *py_models(PyObject *self, PyObject *unused)
{
    PyObject *l = PyList_New(0);
    for (size_t i = 0; l && i < mote_nmodels; i++) {
        PyObject *n = PyUnicode_FromString(mote_models[i]->name);
        if (!n || PyList_Append(l, n)) {
            Py_XDECREF(n);
            Py_CLEAR(l);
        } else {
            Py_DECREF(n);
        }
    }
    return l;
}

/* commands(model) -> [(name, aliases, args, synopsis, summary, help)]: every command a script
 * of the model can give, from the tables `mote help` prints (plot's args with the model's own
 * options); the Python objects' generated methods are made from them */
static PyObject *py_commands(PyObject *self, PyObject *args)
{
    const char *name;
    if (!PyArg_ParseTuple(args, "s", &name))
        return NULL;
    const mote_model *m = NULL;
    for (size_t i = 0; i < mote_nmodels; i++)
        if (!strcmp(mote_models[i]->name, name))
            m = mote_models[i];
    if (!m)
        return PyErr_Format(MoteError, "no model named '%s'", name);
    PyObject *l = PyList_New(0);
    const mote_cmd *c;
    for (size_t k = 0; l && (c = mote_script_command_at(m, k)); k++) {
        const int plot = !strcmp(c->name, "plot") && m->plot_opts;
        PyObject *spec = plot ? PyUnicode_FromFormat("%s %s", c->args, m->plot_opts)
                              : PyUnicode_FromString(c->args ? c->args : "");
        PyObject *t = spec ? Py_BuildValue("(szNzzz)", c->name, c->aliases, spec, c->synopsis,
                                           c->summary, c->help)
                           : NULL;
        if (!t || PyList_Append(l, t))
            Py_CLEAR(l);
        Py_XDECREF(t);
    }
    return l;
}

/* main(argv) -> exit status: the mote program (`python -m mote ...`), its output on the
 * process's stdout and stderr (Python's own streams flushed first) */
static PyObject *py_main(PyObject *self, PyObject *args)
{
    PyObject *list;
    if (!PyArg_ParseTuple(args, "O!", &PyList_Type, &list))
        return NULL;
    const Py_ssize_t n = PyList_Size(list);
    char **argv = calloc((size_t)n + 1, sizeof *argv);
    if (!argv)
        return PyErr_NoMemory();
    int ok = 1;
    for (Py_ssize_t i = 0; i < n && ok; i++) {
        const char *a = PyUnicode_Check(PyList_GET_ITEM(list, i))
                            ? PyUnicode_AsUTF8(PyList_GET_ITEM(list, i)) : NULL;
        if (!a && !PyErr_Occurred())
            PyErr_SetString(PyExc_TypeError, "main: the arguments must be strings");
        ok = a && (argv[i] = strdup(a)) != NULL;
        if (a && !ok)
            PyErr_NoMemory();
    }
    int rc = 0;
    if (ok) {
        Py_BEGIN_ALLOW_THREADS
        rc = mote_main((int)n, argv, mote_models, mote_nmodels);
        fflush(stdout);
        fflush(stderr);
        Py_END_ALLOW_THREADS
    }
    for (Py_ssize_t i = 0; i < n; i++)
        free(argv[i]);
    free(argv);
    return ok ? PyLong_FromLong(rc) : NULL;
}

/* variants(model) -> "a|b" (the first the default), or None */
static PyObject *py_variants(PyObject *self, PyObject *args)
{
    const char *name;
    if (!PyArg_ParseTuple(args, "s", &name))
        return NULL;
    for (size_t i = 0; i < mote_nmodels; i++)
        if (strcmp(mote_models[i]->name, name) == 0) {
            if (mote_models[i]->variants)
                return PyUnicode_FromString(mote_models[i]->variants);
            Py_RETURN_NONE;
        }
    PyErr_Format(MoteError, "no model '%s'", name);
    return NULL;
}

static PyMethodDef methods[] = {
    {"variants", py_variants, METH_VARARGS, "variants(model) -> 'a|b' or None"},
    {"main", py_main, METH_VARARGS, "main(argv) -> exit status: the mote program"},
    {"run", (PyCFunction)(void (*)(void))py_run, METH_VARARGS | METH_KEYWORDS,
     "run(text, name, params=None, check_only=False, progress=None) -> (printed, warnings)"},
    {"commands", py_commands, METH_VARARGS,
     "commands(model) -> [(name, aliases, args, synopsis, summary, help)]: the commands of a "
     "script of that model"},
    {"models", py_models, METH_NOARGS, "the names of the models of this build"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_mote",
                                    "mote's C extension (use the package mote)", -1, methods,
                                    NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__mote(void)
{
    import_array();
    if (PyType_Ready(&SessionType) < 0)
        return NULL;
    PyObject *m = PyModule_Create(&module);
    if (!m)
        return NULL;
    MoteError = PyErr_NewExceptionWithDoc("mote.MoteError",
                                          "an error mote reports: the message names the file, "
                                          "line and column ('FILE:LINE:COL: error: ...')",
                                          NULL, NULL);
    Py_INCREF(&SessionType);
    if (!MoteError || PyModule_AddObject(m, "MoteError", MoteError) ||
        PyModule_AddObject(m, "Session", (PyObject *)&SessionType) ||
        PyModule_AddStringConstant(m, "version", MOTE_VERSION)) {
        Py_DECREF(m);
        return NULL;
    }
    Py_INCREF(MoteError);
    return m;
}
