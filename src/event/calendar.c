/* calendar.c: the event calendar's slower half (spec 6.5, Paul 2007): sizing the buckets and
 * filing every particle at a rebuild, and moving the next bucket's events into the heap. The
 * per-event operations (heap, insertion, removal, the walk ahead) are inline in internal.h. */
#include "internal.h"


/* The heap is empty: move on bucket by bucket until one holds events, and load it into the
 * heap. Each time the circular array wraps, the overflow list is sorted out again (its events
 * were at least a full lap ahead when inserted, so none is missed). Returns -1 when no event
 * with a finite time is left. */
int ev_cal_refill(mote_ev *ev)
{
    mote_ev_cold *C = ev->pc;
    const uint32_t mask = ev->nbuckets - 1;
    uint32_t idle = 0;
    while (ev->heap_n == 0) {
        ev->bucket_cur++;
        uint32_t slot = (uint32_t)(ev->bucket_cur & (int64_t)mask);
        if (slot == 0) {
            for (uint32_t e = cal_take(ev, ev->nbuckets); e != MOTE_EV_NIL;) {
                uint32_t next = C[e].cal_next;
                cal_insert(ev, e);
                e = next;
            }
        }
        for (uint32_t e = cal_take(ev, slot); e != MOTE_EV_NIL;) {
            uint32_t next = C[e].cal_next;
            heap_push(ev, e);
            e = next;
        }
        ev->walk = ev->n;
        if (ev->heap_n == 0 && ++idle > ev->nbuckets) {
            /* a whole lap found nothing: jump to the lap of the earliest overflow event */
            int64_t first = INT64_MAX;
            for (uint32_t e = ev->bucket[ev->nbuckets]; e != MOTE_EV_NIL; e = C[e].cal_next) {
                int64_t b = cal_index(ev, C[e].t_ev);
                if (b < first)
                    first = b;
            }
            if (first == INT64_MAX)
                return -1;
            ev->bucket_cur = (first & ~(int64_t)mask) - 1;
            idle = 0;
        }
    }
    return 0;
}

/* Fill the calendar with every particle's predicted event (index order). The bucket width is
 * chosen so that about HEAP_TARGET events fall into one bucket, from the mean time to the next
 * event just predicted; the circular array spans about 8 such mean times. This tuning is a
 * function of the state alone and never changes the event order. */
int ev_cal_init(mote_ev *ev, mote_err *err)
{
    const uint32_t n = ev->n;
    mote_ev_cold *C = ev->pc;
    uint32_t nb = 1;
    double inv = 0;
    if (!ev->heap_only) {
        double sum = 0;
        uint32_t cnt = 0;
        for (uint32_t i = 0; i < n; i++) {
            double dt = C[i].t_ev - ev->clock;
            if (dt < ev->t_rebuild) {
                sum += dt;
                cnt++;
            }
        }
        double mean = cnt ? sum / cnt : 0;
        if (mean > 0) {
            double width = HEAP_TARGET * mean / n;
            double want = 8.0 * mean / width;
            while (nb < want && nb < (1u << 26))
                nb *= 2;
            inv = 1.0 / width;
        }
    }
    if (nb != ev->nbuckets || !ev->bucket) {
        free(ev->bucket); /* refilled below: free first, so old and new never coexist */
        ev->nbuckets = 0;
        uint32_t *b = malloc(((size_t)nb + 1) * sizeof *b);
        ev->bucket = b;
        if (!b)
            return mote_fail(err, MOTE_ENOMEM, "out of memory for %u calendar buckets", nb);
        ev->nbuckets = nb;
        ev_hint_huge_pages(b, ((size_t)nb + 1) * sizeof *b);
    }
    for (uint32_t s = 0; s <= nb; s++)
        ev->bucket[s] = MOTE_EV_NIL;
    ev->bucket_inv = inv;
    ev->bucket_cur = cal_index(ev, ev->clock);
    ev->walk = n;
    ev->heap_n = 0;
    /* the slots beyond heap_n hold leftovers of the past; clear them so that a rebuilt state is
     * the same bytes whatever its history (save -> load must give back the saved state) */
    memset(ev->heap, 0, (size_t)n * sizeof *ev->heap);
    memset(ev->heap_t, 0, (size_t)n * sizeof *ev->heap_t);
    for (uint32_t i = 0; i < n; i++)
        cal_insert(ev, i);
    return MOTE_OK;
}
