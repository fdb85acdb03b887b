# stability-stab-case-2.awk: from scripts/bench/stability.sh (stab_case): rc, cond (4 fields),
# the --verify run's figures (7 fields: stability-verify.awk), singular (1: its fresh
# factorization found the stiffness singular, -1: it failed otherwise, -2: it timed out)
# -> the verdict
{
        rc = $1; cond = $2; vd = $8; rr = $9; bad = $7; sing = $13
        if (rc != 0) { print (rc == 1 ? "loud" : (rc == 124 ? "timeout" : "error")); exit }
        if (sing > 0) { print "SILENT-singular-K"; exit }
        if (sing == -2) { print "verify-timeout"; exit }
        if (sing < 0 || vd == "NaN") { print "error"; exit }
        if (vd + 0 <= 1e-8 && bad == 0) { print "accurate"; exit }
        if (cond != "NaN" && vd + 0 <= cond * 1e-16 && rr + 0 <= 1e-8 && bad == 0) { print "as-fresh"; exit }
        print "SILENT" }
