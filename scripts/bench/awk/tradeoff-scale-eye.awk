# tradeoff-scale-eye.awk: from scripts/bench/tradeoff.sh (scale_eye)
/^  mesh_size:/ { inb = 1; print; next }
inb && /^    [a-z_]+: *[0-9.]+ mm/ { match($0, /[0-9.]+ mm/); v = substr($0, RSTART, RLENGTH - 3) * f
    sub(/[0-9.]+ mm/, sprintf("%.4g mm", v)); print; next }
inb && !/^    / { inb = 0 }
{ print }
