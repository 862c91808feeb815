function [pt,ok]=hopf_at_tau(funcs,ip,hbr,curve,tau)
%% Hopf point at exactly this tau, corrected in (k, c) (the pinning z(0)=0
% active) from the linear interpolation between the two points of the Hopf
% curve (sorted by tau) that bracket tau: near tau = 0.6 the curve is steep
% (dk/dtau ~ -60), and Newton from the nearest point alone failed there.
% (curve of one point: correct from it)
if numel(curve)==1
    pt=curve;
else
    taus=arrayfun(@(p)p.parameter(ip.tau),curve);
    j=find(taus<=tau,1,'last');
    if isempty(j), j=1; end
    j=min(j,numel(curve)-1);
    w=(tau-taus(j))/(taus(j+1)-taus(j));
    pt=p_axpy(w,curve(j+1),p_axpy(1-w,curve(j),[]));
end
pt.parameter(ip.tau)=tau;
mth=hbr.method.point; mth.extra_condition=1;
[pt,ok]=p_correc(funcs,pt,[ip.k,ip.c],[],mth);
end
