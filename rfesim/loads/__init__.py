"""Load modules: one physical term each (eq. 8.95). Each adds global forces and moments
(about RFE centres) into shared accumulators; ``rfesim.model.assemble`` projects them
onto the generalised coordinates. A scene only calls the modules it contains."""
